#pragma once
// Map metrics against a simulated ground truth: ghost voxels (occupied where only people
// ever were) and static coverage (static surface voxels seen by the camera that the map
// has occupied).
#include <octomap/OcTree.h>
#include <opencv2/core.hpp>

#include "gmc/datasets/frame.h"

namespace gmc::mapping {

struct MapQuality {
  size_t dynamic_only_voxels = 0;     ///< voxels where only people were ever seen
  size_t ghost_voxels = 0;            ///< of those, occupied in the map
  size_t static_voxels_seen = 0;      ///< voxels holding a static surface seen by the camera
  size_t static_voxels_occupied = 0;  ///< of those, occupied in the map
  double static_coverage() const {
    return static_voxels_seen ? static_cast<double>(static_voxels_occupied) / static_voxels_seen : 0.0;
  }
};

/// Accumulates, from ground-truth frames (depth, mask, pose), which voxels hold a static
/// surface and which only ever held people. Same voxel grid as the map (resolution), same
/// pixel sampling and range as the map builder, so both see the same rays.
class GroundTruthVoxels {
 public:
  GroundTruthVoxels(double resolution, double max_range, int pixel_step);
  void addFrame(const datasets::RgbdFrame& frame, const cv::Mat& dynamic_mask,
                const Isometry& T_world_camera);
  MapQuality evaluate(const octomap::OcTree& map) const;

 private:
  octomap::OcTree grid_;  // only for coordinate -> key
  double max_range_;
  int step_;
  octomap::KeySet static_, dynamic_;
};

std::string toJson(const MapQuality& q);

}  // namespace gmc::mapping
