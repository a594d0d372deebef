#pragma once
// Map metrics against a simulated ground truth: ghost voxels (occupied where only people
// ever were) and static coverage (static surface voxels seen by the camera that the map
// has occupied).
#include <octomap/OcTree.h>
#include <opencv2/core.hpp>

#include "gmc/datasets/frame.h"
#include "gmc/mapping/static_map.h"

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
/// surface and which only ever held people: the voxel of every sampled pixel's endpoint
/// goes to the static or the dynamic key set. Same voxel grid as the map (resolution),
/// same pixel sampling and range as the map builder, so both see the same rays.
class GroundTruthVoxels {
 public:
  GroundTruthVoxels(double resolution, double max_range, int pixel_step, double min_range = 0.0);
  /// The grid, sampling and depth range of a map built with `map_options`.
  explicit GroundTruthVoxels(const StaticMapOptions& map_options);
  /// dynamic_mask: CV_8UC1 of the depth's size, non-zero = a person (the simulator's
  /// exact mask, not dilated). Throws std::invalid_argument on a wrong type or size.
  void addFrame(const datasets::RgbdFrame& frame, const cv::Mat& dynamic_mask,
                const Isometry& T_world_camera);
  /// Same as gmc::mapping::evaluate(map, *this).
  MapQuality evaluate(const octomap::OcTree& map) const;

  double resolution() const { return grid_.getResolution(); }
  /// Voxels holding a static endpoint of some frame.
  const octomap::KeySet& staticKeys() const { return static_; }
  /// Voxels holding a dynamic endpoint of some frame (may also be static: see evaluate()).
  const octomap::KeySet& dynamicKeys() const { return dynamic_; }

 private:
  octomap::OcTree grid_;  // only for coordinate -> key
  double min_range_, max_range_;
  int step_;
  octomap::KeySet static_, dynamic_;
};

/// Ghost voxels = occupied map voxels among the dynamic-only ones (dynamic keys that are
/// never static); static coverage = occupied fraction of the static keys. `map` must
/// have the ground truth's resolution (std::invalid_argument otherwise); unknown voxels
/// count as not occupied.
MapQuality evaluate(const octomap::OcTree& map, const GroundTruthVoxels& truth);

std::string toJson(const MapQuality& q);

}  // namespace gmc::mapping
