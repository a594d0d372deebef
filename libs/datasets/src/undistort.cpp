#include "gmc/datasets/undistort.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gmc::datasets {

Undistorter::Undistorter(const PinholeCamera& camera, const LensDistortion& d)
    : K_(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1),
      coefficients_(d.k1, d.k2, d.p1, d.p2, d.k3) {}

void Undistorter::apply(RgbdFrame& frame) {
  if (frame.rgb.size() != size_) {
    size_ = frame.rgb.size();
    cv::initUndistortRectifyMap(K_, coefficients_, cv::noArray(), K_, size_, CV_32FC1, map_x_, map_y_);
  }
  cv::Mat rgb, depth;
  cv::remap(frame.rgb, rgb, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  cv::remap(frame.depth, depth, map_x_, map_y_, cv::INTER_NEAREST, cv::BORDER_CONSTANT);
  frame.rgb = rgb;
  frame.depth = depth;
}

void RadialDepthBias::apply(RgbdFrame& frame) {
  if (k_ == 0 || frame.depth.empty()) return;
  const PinholeCamera& c = frame.camera;
  if (factor_.size() != frame.depth.size() || c.fx != camera_.fx || c.fy != camera_.fy || c.cx != camera_.cx ||
      c.cy != camera_.cy) {
    camera_ = c;
    factor_.create(frame.depth.size(), CV_64F);
    for (int v = 0; v < factor_.rows; ++v) {
      const double y = (v - c.cy) / c.fy;
      for (int u = 0; u < factor_.cols; ++u) {
        const double x = (u - c.cx) / c.fx;
        factor_.at<double>(v, u) = 1.0 + k_ * (x * x + y * y);
      }
    }
  }
  for (int v = 0; v < frame.depth.rows; ++v) {
    auto* row = frame.depth.ptr<std::uint16_t>(v);
    const double* f = factor_.ptr<double>(v);
    for (int u = 0; u < frame.depth.cols; ++u)
      if (row[u]) row[u] = static_cast<std::uint16_t>(std::clamp(std::lround(row[u] / f[u]), 1L, 65535L));
  }
}

}  // namespace gmc::datasets
