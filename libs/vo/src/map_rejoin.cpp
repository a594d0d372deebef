#include "gmc/vo/map_rejoin.h"

#include "gmc/vo/point_correspondences.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace gmc::vo {

bool MapRejoin::waiting(int map) const {
  return std::any_of(waiting_.begin(), waiting_.end(), [&](const WaitingMap& w) { return w.id == map; });
}

bool MapRejoin::freeze(int map, std::vector<Landmark> landmarks, double stamp) {
  if (!options_.enabled || landmarks.size() < static_cast<size_t>(options_.min_inliers)) return false;
  // Full: the oldest map is the frame the trajectory started in; the newest are the
  // likeliest to be seen again. One of each stays when there is room for two.
  if (static_cast<int>(waiting_.size()) >= options_.max_maps) {
    if (options_.max_maps < 2) return false;
    waiting_.erase(waiting_.begin() + 1);
  }
  // The most often re-observed first: they are the furniture that held the pose longest.
  std::stable_sort(landmarks.begin(), landmarks.end(),
                   [](const Landmark& a, const Landmark& b) { return a.hits_in_place > b.hits_in_place; });
  if (landmarks.size() > static_cast<size_t>(options_.max_landmarks))
    landmarks.resize(static_cast<size_t>(options_.max_landmarks));
  WaitingMap w;
  w.id = map;
  w.frozen = std::move(landmarks);
  w.frozen_set.descriptors.create(static_cast<int>(w.frozen.size()), 32, CV_8UC1);
  for (size_t i = 0; i < w.frozen.size(); ++i) {
    std::memcpy(w.frozen_set.descriptors.ptr<std::uint8_t>(static_cast<int>(i)), w.frozen[i].descriptor.data(), 32);
    w.frozen_set.keypoints.emplace_back(0.f, 0.f, 7.f);
    // Exhaustive matching skips reference features without depth; every frozen landmark
    // has a position (in frozen), so each gets a placeholder in front of the camera.
    w.frozen_set.points.emplace_back(0, 0, 1);
  }
  w.frozen_at = stamp;
  if (waiting_.empty()) tracked_frames_ = 0;
  waiting_.push_back(std::move(w));
  return true;
}

std::vector<Landmark> MapRejoin::release(int map) {
  std::vector<Landmark> out;
  for (auto it = waiting_.begin(); it != waiting_.end(); ++it) {
    if (it->id != map) continue;
    out.swap(it->frozen);
    waiting_.erase(it);
    break;
  }
  return out;
}

std::vector<int> MapRejoin::waitingMaps() const {
  std::vector<int> ids;
  for (const auto& w : waiting_) ids.push_back(w.id);
  return ids;
}

std::vector<int> MapRejoin::giveUpExpired(double stamp) {
  std::vector<int> given_up;
  for (const auto& w : waiting_)
    if (stamp - w.frozen_at > options_.max_seconds) given_up.push_back(w.id);
  for (int id : given_up) release(id);
  return given_up;
}

std::optional<RejoinFound> MapRejoin::attempt(const features::Frontend& frontend, const features::FeatureSet& cur,
                                              const Isometry& T_world_cur, const PinholeCamera& camera,
                                              RejoinAttempt* report, int only) {
  RejoinAttempt local;
  RejoinAttempt& r = report ? *report : local;
  r = RejoinAttempt{};
  if (!active()) return std::nullopt;
  if (tracked_frames_++ % options_.every_frames != 0) return std::nullopt;
  // One waiting map per attempt, in turn: the matching cost stays that of one map.
  auto chosen = waiting_.begin() + static_cast<long>(turn_++ % waiting_.size());
  if (only >= 0) {
    chosen = std::find_if(waiting_.begin(), waiting_.end(), [&](const WaitingMap& w) { return w.id == only; });
    if (chosen == waiting_.end()) return std::nullopt;
  }
  WaitingMap& map = *chosen;
  r.map = map.id;
  const std::optional<Isometry> found = correction(frontend, map, cur, T_world_cur, camera, r);
  if (!found) {
    map.candidate.reset();
    return std::nullopt;
  }
  // One attempt can be a coincidence of look-alike corners; the same correction found
  // again at the map's next attempt, from another view, is not.
  const bool agrees = map.candidate && [&] {
    const Isometry d = map.candidate->inverse() * *found;
    return d.translation().norm() <= options_.agree_translation &&
           Eigen::AngleAxisd(d.linear()).angle() <= options_.agree_rotation * M_PI / 180.0;
  }();
  map.candidate = found;
  if (!agrees) return std::nullopt;
  r.confirmed = true;
  return RejoinFound{map.id, *found};
}

std::optional<Isometry> MapRejoin::correction(const features::Frontend& frontend, const WaitingMap& map,
                                              const features::FeatureSet& cur, const Isometry& T_world_cur,
                                              const PinholeCamera& camera, RejoinAttempt& r) {
  // 3-D correspondences: frozen landmark (old world) <- current keypoint (camera frame).
  PointCorrespondences c;
  for (const auto& m : frontend.matchExhaustive(map.frozen_set, cur))
    if (cur.hasDepth(m.cur)) c.add(map.frozen[static_cast<size_t>(m.ref)].position, cur, m.cur);
  r.matches = c.size();
  if (r.matches < options_.min_inliers) return std::nullopt;
  // The pose in the old map, refined on the inliers' pixels and depths as any tracked pose.
  const CorrespondenceFit fit = fitCorrespondences(c, c.all(), Isometry::Identity(), options_.ransac_iterations, rng_,
                                                   threshold_, camera, refinement_);
  r.inliers = static_cast<int>(fit.members.size());
  if (r.inliers < options_.min_inliers) return std::nullopt;
  const RefinementResult& refined = fit.refined;
  r.inliers = refined.inliers;
  if (refined.inliers < options_.min_inliers) return std::nullopt;
  const Isometry T_old_cur = refined.T_cur_ref.inverse();
  return T_old_cur * T_world_cur.inverse();
}

}  // namespace gmc::vo
