#pragma once
// 3-D correspondences of one frame's features with points of a reference frame (a map's
// world, another camera), and the pose they give: 3-point RANSAC on the in-place test and
// the refinement on the sampled pose's in-place ones. Shared by the rejoin (a frame
// against a map left behind) and the hindsight (a past frame against today's map, or
// against the frame after it). No I/O.
#include <vector>

#include "gmc/features/frontend.h"
#include "gmc/vo/background.h"
#include "gmc/vo/in_place_threshold.h"
#include "gmc/vo/pose_refinement.h"

namespace gmc::vo {

struct PointCorrespondences {
  std::vector<Eigen::Vector3d> reference;  ///< where the point is (reference frame)
  std::vector<Eigen::Vector3d> camera;     ///< the feature's point (camera frame)
  std::vector<Eigen::Vector2d> pixels;     ///< the feature's keypoint
  std::vector<int> feature;                ///< the feature's index
  int size() const { return static_cast<int>(reference.size()); }
  /// Feature `index` of `frame` (which has depth there) is the point `reference_point`.
  void add(const Eigen::Vector3d& reference_point, const features::FeatureSet& frame, int index);
  std::vector<int> all() const;  ///< every correspondence's index
  bool inPlace(const Isometry& T_reference_camera, int i, const InPlaceThreshold& threshold) const;
  /// The correspondences of `pool` in place under T_reference_camera.
  std::vector<int> inPlace(const Isometry& T_reference_camera, const std::vector<int>& pool,
                           const InPlaceThreshold& threshold) const;
};

struct CorrespondenceFit {
  std::vector<int> members;  ///< the pool's correspondences in place under the sampled pose
  RefinementResult refined;  ///< the refinement on them (T_cur_ref maps reference points into the camera)
};

/// 3-point RANSAC over `pool` (each sample scored by the pool's correspondences in place;
/// `fallback` when no sample is usable) and the refinement of the best on its members.
CorrespondenceFit fitCorrespondences(const PointCorrespondences& c, const std::vector<int>& pool,
                                     const Isometry& fallback, int iterations, Xorshift64& rng,
                                     const InPlaceThreshold& threshold, const PinholeCamera& camera,
                                     const RefinementOptions& refinement);

}  // namespace gmc::vo
