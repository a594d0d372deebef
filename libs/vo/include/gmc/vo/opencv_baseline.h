#pragma once
// OpenCV rgbd-contrib odometry (frame-to-frame, chained), the baseline the benchmarks
// compare GMC odometry against on the same frames.
#include <opencv2/core.hpp>

#include <memory>
#include <string>

#include "gmc/gmc/types.h"

namespace gmc::vo {

class OpenCvOdometry {
 public:
  /// method: "rgbd" (cv::rgbd::RgbdOdometry), "icp" (ICPOdometry) or "rgbd_icp".
  OpenCvOdometry(const std::string& method, const PinholeCamera& camera);
  ~OpenCvOdometry();

  /// Returns T_world_camera (world = first frame); `ok` is false when OpenCV failed
  /// on this frame (the pose then repeats the last motion).
  Isometry process(const cv::Mat& gray, const cv::Mat& depth16, double depth_units, bool& ok);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gmc::vo
