#include "gmc/vo/opencv_baseline.h"

#include <opencv2/rgbd.hpp>

#include <stdexcept>

namespace gmc::vo {

struct OpenCvOdometry::Impl {
  cv::Ptr<cv::rgbd::Odometry> odometry;
  cv::Mat prev_gray, prev_depth;
  Isometry T_world_cur = Isometry::Identity();
  Isometry last_motion = Isometry::Identity();
};

OpenCvOdometry::OpenCvOdometry(const std::string& method, const PinholeCamera& camera)
    : impl_(std::make_unique<Impl>()) {
  const cv::Mat K = (cv::Mat_<float>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  if (method == "rgbd")
    impl_->odometry = cv::rgbd::RgbdOdometry::create(K);
  else if (method == "icp")
    impl_->odometry = cv::rgbd::ICPOdometry::create(K);
  else if (method == "rgbd_icp")
    impl_->odometry = cv::rgbd::RgbdICPOdometry::create(K);
  else
    throw std::invalid_argument("unknown OpenCV odometry '" + method + "' (rgbd, icp, rgbd_icp)");
}

OpenCvOdometry::~OpenCvOdometry() = default;

Isometry OpenCvOdometry::process(const cv::Mat& gray, const cv::Mat& depth16, double depth_units,
                                 bool& ok) {
  cv::Mat depth;
  depth16.convertTo(depth, CV_32FC1, depth_units);
  depth.setTo(std::numeric_limits<float>::quiet_NaN(), depth16 == 0);
  ok = true;
  if (!impl_->prev_gray.empty()) {
    cv::Mat Rt;  // T_cur_prev: dst_p = Rt * src_p
    const cv::Mat mask;
    ok = impl_->odometry->compute(impl_->prev_gray, impl_->prev_depth, mask, gray, depth, mask, Rt);
    Isometry motion = impl_->last_motion;  // T_prev_cur
    if (ok) {
      Eigen::Matrix4d M;
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) M(r, c) = Rt.at<double>(r, c);
      motion.matrix() = M.inverse();
    }
    impl_->last_motion = motion;
    impl_->T_world_cur = impl_->T_world_cur * motion;
  }
  impl_->prev_gray = gray.clone();
  impl_->prev_depth = depth;
  return impl_->T_world_cur;
}

}  // namespace gmc::vo
