#include "gmc/vo/point_correspondences.h"

#include <numeric>

namespace gmc::vo {

void PointCorrespondences::add(const Eigen::Vector3d& reference_point, const features::FeatureSet& frame, int index) {
  const auto f = static_cast<size_t>(index);
  reference.push_back(reference_point);
  camera.push_back(frame.points[f]);
  pixels.emplace_back(frame.keypoints[f].pt.x, frame.keypoints[f].pt.y);
  feature.push_back(index);
}

std::vector<int> PointCorrespondences::all() const {
  std::vector<int> out(static_cast<size_t>(size()));
  std::iota(out.begin(), out.end(), 0);
  return out;
}

bool PointCorrespondences::inPlace(const Isometry& T_reference_camera, int i, const InPlaceThreshold& threshold) const {
  const auto u = static_cast<size_t>(i);
  return (T_reference_camera * camera[u] - reference[u]).norm() <= threshold.at(camera[u].z());
}

std::vector<int> PointCorrespondences::inPlace(const Isometry& T_reference_camera, const std::vector<int>& pool,
                                               const InPlaceThreshold& threshold) const {
  std::vector<int> out;
  for (int i : pool)
    if (inPlace(T_reference_camera, i, threshold)) out.push_back(i);
  return out;
}

CorrespondenceFit fitCorrespondences(const PointCorrespondences& c, const std::vector<int>& pool,
                                     const Isometry& fallback, int iterations, Xorshift64& rng,
                                     const InPlaceThreshold& threshold, const PinholeCamera& camera,
                                     const RefinementOptions& refinement) {
  const Isometry sampled = ransacRigid(
      pool, iterations, rng, [&](int i) { return c.camera[static_cast<size_t>(i)]; },
      [&](int i) { return c.reference[static_cast<size_t>(i)]; },
      [&](const Isometry& T, double) { return static_cast<double>(c.inPlace(T, pool, threshold).size()); }, fallback);
  CorrespondenceFit fit;
  fit.members = c.inPlace(sampled, pool, threshold);
  std::vector<PointObservation> obs;
  for (int i : fit.members) {
    const auto u = static_cast<size_t>(i);
    obs.push_back({c.reference[u], c.pixels[u], c.camera[u].z(), 1.0});
  }
  fit.refined = refinePose(obs, sampled.inverse(), camera, refinement);
  return fit;
}

}  // namespace gmc::vo
