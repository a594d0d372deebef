#pragma once
// Test helper: the features a pinhole camera sees of given 3-D points with given
// descriptors (the scenes of test_map_rejoin.cpp and test_hindsight.cpp).
#include <array>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "gmc/features/frontend.h"

namespace gmc::test {

/// 256 random bits: any two such descriptors differ by about 128.
inline std::array<std::uint8_t, 32> randomDescriptor(std::mt19937& rng) {
  std::array<std::uint8_t, 32> d{};
  for (auto& b : d) b = static_cast<std::uint8_t>(rng() & 0xff);
  return d;
}

/// Collects the points a camera sees (camera frame; nearer than 0.3 m or outside the
/// image: not seen) into a FeatureSet.
class SeenFeatures {
 public:
  explicit SeenFeatures(const PinholeCamera& camera) : camera_(camera) {
    set_.width = camera.width;
    set_.height = camera.height;
  }
  void add(const Eigen::Vector3d& p_camera, const std::array<std::uint8_t, 32>& descriptor) {
    if (p_camera.z() <= 0.3) return;
    const Eigen::Vector2d uv = camera_.project(p_camera);
    if (!camera_.inside(uv.x(), uv.y())) return;
    set_.keypoints.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 7.f);
    set_.points.push_back(p_camera);
    descriptors_.push_back(descriptor);
  }
  features::FeatureSet take() {
    set_.descriptors.create(static_cast<int>(descriptors_.size()), 32, CV_8UC1);
    for (size_t i = 0; i < descriptors_.size(); ++i)
      std::memcpy(set_.descriptors.ptr<std::uint8_t>(static_cast<int>(i)), descriptors_[i].data(), 32);
    return std::move(set_);
  }

 private:
  const PinholeCamera& camera_;
  features::FeatureSet set_;
  std::vector<std::array<std::uint8_t, 32>> descriptors_;
};

}  // namespace gmc::test
