#pragma once
// Writes frames as a TUM folder (rgb/, depth/, rgb.txt, depth.txt) for the apps' tests.
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gmc/datasets/frame.h"

namespace gmc::testdata {

/// Frame i is rgb/i.png and depth/i.png; the lists carry `list_stamps` when given (to test
/// odd stamps), else the frames' own stamps.
inline std::string writeTumFolder(const std::string& dir, const std::vector<gmc::datasets::RgbdFrame>& frames,
                                  std::vector<double> list_stamps = {}) {
  std::filesystem::create_directories(dir + "/rgb");
  std::filesystem::create_directories(dir + "/depth");
  if (list_stamps.empty())
    for (const auto& f : frames) list_stamps.push_back(f.stamp);
  std::ofstream rgb(dir + "/rgb.txt"), depth(dir + "/depth.txt");
  for (size_t i = 0; i < frames.size(); ++i) {
    const std::string name = std::to_string(i) + ".png";
    cv::imwrite(dir + "/rgb/" + name, frames[i].rgb);
    cv::imwrite(dir + "/depth/" + name, frames[i].depth);
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f", list_stamps[i]);
    rgb << stamp << " rgb/" << name << "\n";
    depth << stamp << " depth/" << name << "\n";
  }
  return dir;
}

}  // namespace gmc::testdata
