#include "gmc/vo/map_rejoin.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

namespace gmc::vo {

void MapRejoin::freeze(std::vector<Landmark> landmarks, double stamp) {
  if (active() || !options_.enabled || landmarks.size() < static_cast<size_t>(options_.min_inliers)) return;
  // The most often re-observed first: they are the furniture that held the pose longest.
  std::stable_sort(landmarks.begin(), landmarks.end(),
                   [](const Landmark& a, const Landmark& b) { return a.hits_in_place > b.hits_in_place; });
  if (landmarks.size() > static_cast<size_t>(options_.max_landmarks))
    landmarks.resize(static_cast<size_t>(options_.max_landmarks));
  frozen_ = std::move(landmarks);
  frozen_set_ = features::FeatureSet{};
  frozen_set_.descriptors.create(static_cast<int>(frozen_.size()), 32, CV_8UC1);
  for (size_t i = 0; i < frozen_.size(); ++i) {
    std::memcpy(frozen_set_.descriptors.ptr<std::uint8_t>(static_cast<int>(i)), frozen_[i].descriptor.data(), 32);
    frozen_set_.keypoints.emplace_back(0.f, 0.f, 7.f);
    // Exhaustive matching skips reference features without depth; every frozen landmark
    // has a position (in frozen_), so each gets a placeholder in front of the camera.
    frozen_set_.points.emplace_back(0, 0, 1);
  }
  frozen_at_ = stamp;
  tracked_frames_ = 0;
  candidate_.reset();
}

std::vector<Landmark> MapRejoin::release() {
  std::vector<Landmark> out;
  out.swap(frozen_);
  frozen_set_ = features::FeatureSet{};
  candidate_.reset();
  return out;
}

std::optional<Isometry> MapRejoin::attempt(const features::Frontend& frontend, const features::FeatureSet& cur,
                                           const Isometry& T_world_cur, const PinholeCamera& camera, double stamp,
                                           RejoinAttempt* report) {
  RejoinAttempt local;
  RejoinAttempt& r = report ? *report : local;
  r = RejoinAttempt{};
  if (!active()) return std::nullopt;
  if (stamp - frozen_at_ > options_.max_seconds) {
    release();
    return std::nullopt;
  }
  if (tracked_frames_++ % options_.every_frames != 0) return std::nullopt;
  const std::optional<Isometry> found = correction(frontend, cur, T_world_cur, camera, r);
  if (!found) {
    candidate_.reset();
    return std::nullopt;
  }
  // One attempt can be a coincidence of look-alike corners; the same correction found
  // again frames later, from another view, is not.
  const bool agrees = candidate_ && [&] {
    const Isometry d = candidate_->inverse() * *found;
    return d.translation().norm() <= options_.agree_translation &&
           Eigen::AngleAxisd(d.linear()).angle() <= options_.agree_rotation * M_PI / 180.0;
  }();
  candidate_ = found;
  if (!agrees) return std::nullopt;
  r.confirmed = true;
  return found;
}

std::optional<Isometry> MapRejoin::correction(const features::Frontend& frontend, const features::FeatureSet& cur,
                                              const Isometry& T_world_cur, const PinholeCamera& camera,
                                              RejoinAttempt& r) {
  // 3-D correspondences: frozen landmark (old world) <- current keypoint (camera frame).
  std::vector<Eigen::Vector3d> old_points, cur_points;
  std::vector<Eigen::Vector2d> pixels;
  for (const auto& m : frontend.matchExhaustive(frozen_set_, cur)) {
    if (!cur.hasDepth(m.cur)) continue;
    old_points.push_back(frozen_[static_cast<size_t>(m.ref)].position);
    cur_points.push_back(cur.points[static_cast<size_t>(m.cur)]);
    const auto& kp = cur.keypoints[static_cast<size_t>(m.cur)].pt;
    pixels.emplace_back(kp.x, kp.y);
  }
  const int n = static_cast<int>(old_points.size());
  r.matches = n;
  if (n < options_.min_inliers) return std::nullopt;
  auto inliers_of = [&](const Isometry& T_old_cur, std::vector<int>* out) {
    int count = 0;
    for (int i = 0; i < n; ++i) {
      const double err = (T_old_cur * cur_points[static_cast<size_t>(i)] - old_points[static_cast<size_t>(i)]).norm();
      if (err > threshold_.at(cur_points[static_cast<size_t>(i)].z())) continue;
      ++count;
      if (out) out->push_back(i);
    }
    return count;
  };
  std::vector<int> all(static_cast<size_t>(n));
  std::iota(all.begin(), all.end(), 0);
  const Isometry best = ransacRigid(
      all, options_.ransac_iterations, rng_, [&](int i) { return cur_points[static_cast<size_t>(i)]; },
      [&](int i) { return old_points[static_cast<size_t>(i)]; },
      [&](const Isometry& T) { return static_cast<double>(inliers_of(T, nullptr)); }, Isometry::Identity());
  std::vector<int> inliers;
  r.inliers = inliers_of(best, &inliers);
  if (r.inliers < options_.min_inliers) return std::nullopt;
  // The pose in the old map, refined on the inliers' pixels and depths as any tracked pose.
  std::vector<PointObservation> obs;
  for (int i : inliers)
    obs.push_back({old_points[static_cast<size_t>(i)], pixels[static_cast<size_t>(i)],
                   cur_points[static_cast<size_t>(i)].z(), 1.0});
  const RefinementResult refined = refinePose(obs, best.inverse(), camera, refinement_);
  r.inliers = refined.inliers;
  if (refined.inliers < options_.min_inliers) return std::nullopt;
  const Isometry T_old_cur = refined.T_cur_ref.inverse();
  return T_old_cur * T_world_cur.inverse();
}

}  // namespace gmc::vo
