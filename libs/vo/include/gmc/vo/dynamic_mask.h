#pragma once
// Per-pixel dynamic mask. Two kinds of evidence seed a flood fill over depth-continuous
// pixels: GMC's dynamic keypoints, and pixels whose 3-D point lies where an earlier frame's
// ray saw free space (something moved in there). The fill is bounded to the neighbourhood of
// that evidence, so that a walker's untextured parts (no keypoints) are masked too while
// the floor it stands on is not.
#include <deque>

#include <opencv2/core.hpp>

#include "gmc/vo/odometry.h"

namespace gmc::vo {

/// INI section [DynamicMask].
struct DynamicMaskOptions {
  bool flood_fill = true;          ///< grow the evidence over continuous depth
  double depth_step = 0.04;        ///< m, max depth jump between neighbouring pixels
  int cell_margin = 1;             ///< growth from keypoints stays within dynamic cells dilated by this many cells
  int seed_radius = 6;             ///< px disc marked around every dynamic keypoint
  int dilate = 4;                  ///< px final dilation (depth edges of people bleed)
  int scale = 2;                   ///< work at 1/scale resolution for speed
  bool free_space_check = true;    ///< also use the free-space evidence of earlier frames
  int history_frames = 30;         ///< oldest reference frame, in tracked frames back
  int references = 5;              ///< reference frames, evenly spaced over the history
  double free_space_margin = 0.05; ///< m, a point must lie this far in front of a reference surface ...
  double free_space_margin_z2 = 0.01;  ///< ... plus this times depth² (sensor noise grows with z²)
  int free_space_scale = 4;        ///< the check runs at 1/this resolution
  int min_violation_area = 12;     ///< px at that resolution: smaller groups are sensor noise
  int violation_margin = 12;       ///< px (full resolution): growth from violations stays this close to them

  template <class V>
  void visit(V& v) {
    v("flood_fill", flood_fill, "grow dynamic evidence over continuous depth");
    v("depth_step", depth_step, 1e-3, 1.0, "m, max depth jump between neighbours");
    v("cell_margin", cell_margin, 0, 10, "growth bound: dynamic cells dilated by this many cells");
    v("seed_radius", seed_radius, 0, 100, "px disc around each dynamic keypoint");
    v("dilate", dilate, 0, 100, "px dilation of the final mask");
    v("scale", scale, 1, 8, "downscale factor of the flood fill");
    v("free_space_check", free_space_check, "mark points lying in space earlier frames saw free");
    v("history_frames", history_frames, 1, 300, "oldest reference frame, tracked frames back");
    v("references", references, 1, 30, "reference frames, evenly spaced over the history");
    v("free_space_margin", free_space_margin, 0.0, 10.0, "m, constant part of the free-space margin");
    v("free_space_margin_z2", free_space_margin_z2, 0.0, 10.0, "1/m, depth² part of the margin");
    v("free_space_scale", free_space_scale, 1, 16, "downscale factor of the free-space check");
    v("min_violation_area", min_violation_area, 1, 100000, "px, smaller violation groups are ignored");
    v("violation_margin", violation_margin, 0, 500, "px, growth bound around violations");
  }
};

/// Builds the mask frame after frame; remembers recent tracked frames' depth and pose for
/// the free-space check.
class DynamicMaskBuilder {
 public:
  explicit DynamicMaskBuilder(const DynamicMaskOptions& options = {});

  /// CV_8UC1 mask, 255 = dynamic, same size as `depth` (CV_16UC1 raw units).
  cv::Mat build(const FrameTracking& tracking, const cv::Mat& depth, double depth_units,
                const PinholeCamera& camera);

  /// The free-space evidence of the last build() (CV_8UC1 at 1/free_space_scale; empty
  /// when the check did not run), for overlays and tests.
  const cv::Mat& lastViolations() const { return violations_; }

 private:
  struct Reference {
    cv::Mat min_depth;  ///< CV_32F metres, 3x3 minimum (0 where any reading is missing)
    Isometry T_camera_world = Isometry::Identity();
  };
  cv::Mat freeSpaceViolations(const cv::Mat& small_depth, const PinholeCamera& camera,
                              const Isometry& T_world_camera) const;

  DynamicMaskOptions options_;
  std::deque<Reference> history_;
  cv::Mat violations_;
};

/// Stateless mask from the keypoint evidence alone (no free-space check).
cv::Mat buildDynamicMask(const FrameTracking& tracking, const cv::Mat& depth, double depth_units,
                         const DynamicMaskOptions& options);

}  // namespace gmc::vo
