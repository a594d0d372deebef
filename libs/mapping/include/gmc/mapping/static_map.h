#pragma once
// OctoMap of static depth only: dynamic pixels (GMC's mask) add no occupied voxel, and
// their rays still clear the free space in front of the walker.
#include <octomap/OcTree.h>
#include <opencv2/core.hpp>

#include <memory>
#include <string>
#include <vector>

#include "gmc/datasets/frame.h"

namespace gmc::mapping {

/// INI section [Mapping].
struct StaticMapOptions {
  double resolution = 0.05;       ///< m, voxel edge
  double min_range = 0.3;         ///< m, closer depth is ignored
  double max_range = 4.0;         ///< m, farther depth only clears free space up to here
  int pixel_step = 4;             ///< use every N-th pixel in u and v (rays per frame / N^2)
  int insert_every_n_frames = 1;  ///< insert every N-th frame offered to insertFrame()
  double prob_hit = 0.7;          ///< OctoMap defaults: hit 0.7, miss 0.4, clamping 0.12/0.97
  double prob_miss = 0.4;
  double clamp_min = 0.12;
  double clamp_max = 0.97;
  bool discretize = true;         ///< one ray per endpoint voxel (static and dynamic ends)
  bool use_dynamic_mask = true;   ///< false: insert everything (ablation: GMC poses, no mask)
  bool clear_dynamic_rays = true; ///< rays to dynamic pixels clear free space in front of them
  double dynamic_ray_margin = 0.15;  ///< m, stop clearing this far before a dynamic surface
  int mask_dilate_px = 2;         ///< grow the dynamic mask: depth at people's edges bleeds

  template <class V>
  void visit(V& v) {
    v("resolution", resolution, 0.005, 10.0, "m, voxel edge");
    v("min_range", min_range, 0.0, 100.0, "m, closer depth is ignored");
    v("max_range", max_range, 0.1, 100.0, "m, farther depth only clears free space up to here");
    v("pixel_step", pixel_step, 1, 64, "use every N-th pixel in u and v");
    v("insert_every_n_frames", insert_every_n_frames, 1, 1000000,
      "insert every N-th frame offered to the map (1 = all)");
    v("prob_hit", prob_hit, 0.5, 1.0, "occupancy probability of a hit");
    v("prob_miss", prob_miss, 0.0, 0.5, "occupancy probability of a miss");
    v("clamp_min", clamp_min, 0.0, 0.5, "lower clamping probability");
    v("clamp_max", clamp_max, 0.5, 1.0, "upper clamping probability");
    v("discretize", discretize, "discretized insertion (faster, one ray per voxel)");
    v("use_dynamic_mask", use_dynamic_mask, "keep dynamic pixels out of the map");
    v("clear_dynamic_rays", clear_dynamic_rays, "rays to dynamic pixels clear free space");
    v("dynamic_ray_margin", dynamic_ray_margin, 0.0, 10.0, "m kept before a dynamic surface");
    v("mask_dilate_px", mask_dilate_px, 0, 50,
      "px, grow the dynamic mask before insertion (people's depth edges bleed)");
  }
};

struct MapStats {
  size_t frames_inserted = 0;  ///< frames that reached the tree (after insert_every_n_frames)
  size_t leaf_nodes = 0, occupied_leaves = 0, free_leaves = 0;
  size_t memory_bytes = 0;
  double occupied_volume_m3 = 0;
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
};
std::string toJson(const MapStats& stats);
std::string toText(const MapStats& stats);

class StaticMapBuilder {
 public:
  /// Throws std::invalid_argument naming the key when an option is out of range.
  explicit StaticMapBuilder(const StaticMapOptions& options = {});
  const StaticMapOptions& options() const { return options_; }

  /// dynamic_mask: CV_8UC1 of the depth's size, non-zero = dynamic (empty = all static).
  /// T_world_camera: pose of the camera's optical frame in the map's world frame.
  /// Returns false when the frame was skipped (insert_every_n_frames); throws
  /// std::invalid_argument on a mask or depth of the wrong type or size.
  bool insertFrame(const datasets::RgbdFrame& frame, const cv::Mat& dynamic_mask,
                   const Isometry& T_world_camera);

  const octomap::OcTree& tree() const { return *tree_; }
  octomap::OcTree& tree() { return *tree_; }
  MapStats stats() const;
  /// Writes the .bt file (octovis, OctoMap tools) atomically.
  void writeBinary(const std::string& path) const;

 private:
  void sampleEndpoints(const datasets::RgbdFrame& frame, const cv::Mat* mask, const Isometry& T_world_camera);
  void addDynamicRays(const octomap::point3d& origin);

  StaticMapOptions options_;
  std::unique_ptr<octomap::OcTree> tree_;
  size_t frames_offered_ = 0, frames_ = 0;
  // Reused between frames (no allocation in steady state).
  octomap::Pointcloud cloud_;
  octomap::KeySet free_keys_, occupied_keys_, dynamic_keys_;
  octomap::KeyRay ray_;
  std::vector<Eigen::Vector3d> dynamic_ends_;
  cv::Mat dilated_mask_, kernel_;
};

}  // namespace gmc::mapping
