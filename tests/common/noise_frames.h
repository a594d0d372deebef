#pragma once
// Small RGB-D frames of uniform noise (64x48, depth 0.2-4 m): fast inputs for the apps'
// bad-input tests, which look at files and messages, not at tracking.
#include <opencv2/core.hpp>

#include <vector>

#include "gmc/datasets/frame.h"

namespace gmc::testdata {

inline std::vector<gmc::datasets::RgbdFrame> noiseFrames(int n, int seed = 3) {
  std::vector<gmc::datasets::RgbdFrame> frames(static_cast<size_t>(n));
  cv::RNG rng(static_cast<uint64_t>(seed));
  for (int i = 0; i < n; ++i) {
    auto& f = frames[static_cast<size_t>(i)];
    f.stamp = 100.0 + i / 30.0;
    f.rgb.create(48, 64, CV_8UC3);
    f.depth.create(48, 64, CV_16UC1);
    rng.fill(f.rgb, cv::RNG::UNIFORM, 0, 255);
    rng.fill(f.depth, cv::RNG::UNIFORM, 1000, 20000);
    f.camera.fx = 60, f.camera.fy = 60, f.camera.cx = 31.5, f.camera.cy = 23.5;
    f.camera.width = 64, f.camera.height = 48;
  }
  return frames;
}

}  // namespace gmc::testdata
