#pragma once
// Removing lens distortion from registered RGB-D frames (TUM fr1/fr2), and a depth
// sensor's radial depth bias (Bonn's Xtion).
#include <opencv2/core.hpp>

#include "gmc/datasets/camera.h"
#include "gmc/datasets/frame.h"

namespace gmc::datasets {

/// Remaps frames of one camera to the distortion-free pinhole image with the same
/// intrinsics. Colour is interpolated bilinearly; depth (registered to the colour image,
/// so distorted the same way) takes the nearest pixel, so no depth is invented between a
/// person and the wall behind; pixels mapped from outside the image become black / 0.
class Undistorter {
 public:
  Undistorter(const PinholeCamera& camera, const LensDistortion& distortion);
  /// Changes frame.rgb and frame.depth in place (maps built once per image size).
  void apply(RgbdFrame& frame);

 private:
  cv::Matx33d K_;
  cv::Vec<double, 5> coefficients_;
  cv::Size size_;
  cv::Mat map_x_, map_y_;
};

/// A structured-light sensor that reads depth z as z (1 + k r^2), r^2 the squared
/// normalised image radius ((u - cx) / fx)^2 + ((v - cy) / fy)^2: every reading is divided
/// by (1 + k r^2) in place (k = 0: nothing). Bonn's Xtion reads the image corners 7 % short
/// (k = -0.14; doc/datasets.md). The factors are computed once per camera and image size.
class RadialDepthBias {
 public:
  explicit RadialDepthBias(double k = 0) : k_(k) {}
  void apply(RgbdFrame& frame);

 private:
  double k_;
  PinholeCamera camera_;
  cv::Mat factor_;  ///< CV_64F, 1 + k r^2 per pixel
};


}  // namespace gmc::datasets
