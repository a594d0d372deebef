#pragma once
// Hand-made frames whose voxels are known exactly: a 10 x 10 px camera whose pixel rays
// at depth 1.05 m hit the centres of a 10 x 10 patch of 0.1 m voxels (one pixel, one voxel).
#include <octomap/OcTree.h>
#include <opencv2/core.hpp>

#include <set>
#include <tuple>

#include "gmc/datasets/frame.h"

namespace gmc::mapping::testing {

constexpr double kVoxel = 0.1;
constexpr std::uint16_t kWallRaw = 5250;    // 1.05 m: voxel centre row z in [1.0, 1.1]
constexpr std::uint16_t kPersonRaw = 2750;  // 0.55 m: voxels z in [0.5, 0.6]

inline datasets::RgbdFrame patchFrame(std::uint16_t wall_raw = kWallRaw) {
  datasets::RgbdFrame f;
  f.camera.fx = f.camera.fy = 10.5;
  f.camera.cx = f.camera.cy = 4.5;
  f.camera.width = f.camera.height = 10;
  f.rgb = cv::Mat(10, 10, CV_8UC3, cv::Scalar(0, 0, 0));
  f.depth = cv::Mat(10, 10, CV_16UC1, cv::Scalar(wall_raw));
  f.name = "patch";
  return f;
}

/// The 2 x 2 px block in the middle: the "person".
inline const cv::Rect kPersonBox(4, 4, 2, 2);

inline cv::Mat personMask() {
  cv::Mat m = cv::Mat::zeros(10, 10, CV_8UC1);
  m(kPersonBox).setTo(255);
  return m;
}

inline datasets::RgbdFrame patchWithPerson(std::uint16_t person_raw = kPersonRaw) {
  auto f = patchFrame();
  f.depth(kPersonBox).setTo(person_raw);
  return f;
}

inline bool occupiedAt(const octomap::OcTree& t, double x, double y, double z) {
  const auto* n = t.search(x, y, z);
  return n && t.isNodeOccupied(n);
}

inline std::set<std::tuple<int, int, int>> occupiedKeys(const octomap::OcTree& t) {
  std::set<std::tuple<int, int, int>> keys;
  for (auto it = t.begin_leafs(); it != t.end_leafs(); ++it)
    if (t.isNodeOccupied(*it)) {
      const auto k = it.getKey();
      keys.insert({k[0], k[1], k[2]});
    }
  return keys;
}

}  // namespace gmc::mapping::testing
