// Tracks two synthetic frames of a textured wall with the installed odometry; exit 0 when
// the second frame is tracked.
#include <opencv2/core.hpp>

#include <cstdio>

#include "gmc/vo/odometry.h"

int main() {
  cv::Mat gray(240, 320, CV_8UC1);
  cv::RNG rng(3);
  rng.fill(gray, cv::RNG::UNIFORM, 0, 255);
  cv::Mat depth(240, 320, CV_16UC1, cv::Scalar(10000));  // 2 m
  gmc::PinholeCamera camera;
  camera.fx = camera.fy = 270, camera.cx = 160, camera.cy = 120, camera.width = 320, camera.height = 240;
  gmc::vo::RgbdOdometry odometry{gmc::vo::OdometryConfig{}};
  odometry.process(gray, depth, 1.0 / 5000, camera, 0.0);
  const auto second = odometry.process(gray, depth, 1.0 / 5000, camera, 0.033);
  std::printf("consumer: second frame %s\n", gmc::vo::toString(second.state));
  return second.tracked() ? 0 : 1;
}
