#pragma once
// Shi-Tomasi corners (cv::goodFeaturesToTrack) and their sub-pixel refinement
// (cv::cornerSubPix), computed in row strips and corner chunks on OpenCV's thread pool.
// The output is bit-identical to OpenCV's single-threaded calls (tests/features checks
// it on generated and real frames): only the speed changes (doc/performance.md).
#include <opencv2/core.hpp>

#include <vector>

namespace gmc::features {

struct CornerParams {
  int max_corners = 1200;       ///< strongest corners kept (0: all)
  double quality_level = 0.005; ///< minimum eigenvalue relative to the strongest corner
  double min_distance = 10.0;   ///< px between kept corners
  int block_size = 3;           ///< covariance window (px)
};

/// cv::goodFeaturesToTrack(gray, corners, max, quality, min_distance, mask, block_size,
/// false) with `mask` the image minus a `border` px frame; gray is CV_8UC1. `strips`: row
/// strips the work is split into (0: one per OpenCV thread); the result does not depend on it.
std::vector<cv::Point2f> detectCornersInside(const cv::Mat& gray, int border, const CornerParams& params,
                                             int strips = 0);

/// cv::cornerSubPix(gray, corners, (2 half_window + 1)^2, no dead zone, 10 iterations or
/// 0.01 px) on chunks of corners in parallel (each corner is refined on its own); `chunks`
/// 0: four per OpenCV thread.
void refineCornersSubPixel(const cv::Mat& gray, std::vector<cv::Point2f>& corners, int half_window,
                           int chunks = 0);

}  // namespace gmc::features
