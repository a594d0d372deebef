#pragma once
// Per-pixel dynamic mask from GMC's sparse labels: dynamic keypoints seed a flood fill
// over depth-continuous pixels, bounded to the neighbourhood of dynamic GMC cells, so
// that a walker's untextured parts (no keypoints) are masked too.
#include <opencv2/core.hpp>

#include "gmc/vo/odometry.h"

namespace gmc::vo {

/// INI section [DynamicMask].
struct DynamicMaskOptions {
  bool flood_fill = true;          ///< grow dynamic keypoints over continuous depth
  double depth_step = 0.04;        ///< m, max depth jump between neighbouring pixels
  int cell_margin = 1;             ///< growth stays within dynamic cells dilated by this many cells
  int seed_radius = 6;             ///< px disc marked around every dynamic keypoint
  int dilate = 4;                  ///< px final dilation (depth edges of people bleed)
  int scale = 2;                   ///< work at 1/scale resolution for speed

  template <class V>
  void visit(V& v) {
    v("flood_fill", flood_fill, "grow dynamic keypoints over continuous depth");
    v("depth_step", depth_step, 1e-3, 1.0, "m, max depth jump between neighbours");
    v("cell_margin", cell_margin, 0, 10, "growth bound: dynamic cells dilated by this many cells");
    v("seed_radius", seed_radius, 0, 100, "px disc around each dynamic keypoint");
    v("dilate", dilate, 0, 100, "px dilation of the final mask");
    v("scale", scale, 1, 8, "downscale factor of the flood fill");
  }
};

/// CV_8UC1 mask, 255 = dynamic, same size as `depth`.
cv::Mat buildDynamicMask(const FrameTracking& tracking, const cv::Mat& depth, double depth_units,
                         const DynamicMaskOptions& options);

}  // namespace gmc::vo
