#pragma once
// A small RGB-D frame of noise (64x48), the same for the same seed.
#include <opencv2/core.hpp>

#include "gmc/datasets/frame.h"

namespace gmc::testdata {

inline gmc::datasets::RgbdFrame randomFrame(double stamp, unsigned seed, int depth_min = 0,
                                            int depth_max = 30000) {
  cv::RNG rng(seed);
  gmc::datasets::RgbdFrame f;
  f.stamp = stamp;
  f.rgb.create(48, 64, CV_8UC3);
  f.depth.create(48, 64, CV_16UC1);
  rng.fill(f.rgb, cv::RNG::UNIFORM, 0, 255);
  rng.fill(f.depth, cv::RNG::UNIFORM, depth_min, depth_max);
  f.camera.fx = 60, f.camera.fy = 61, f.camera.cx = 31.5, f.camera.cy = 23.5;
  f.camera.width = 64, f.camera.height = 48;
  return f;
}

}  // namespace gmc::testdata
