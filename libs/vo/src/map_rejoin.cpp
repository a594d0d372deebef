#include "gmc/vo/map_rejoin.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>

namespace gmc::vo {

bool MapRejoin::waiting(int map) const {
  return std::any_of(waiting_.begin(), waiting_.end(), [&](const WaitingMap& w) { return w.id == map; });
}

namespace {

/// Descriptors of `landmarks` as a reference FeatureSet for exhaustive matching.
features::FeatureSet descriptorSet(const std::vector<const Landmark*>& landmarks) {
  features::FeatureSet set;
  set.descriptors.create(static_cast<int>(landmarks.size()), 32, CV_8UC1);
  for (size_t i = 0; i < landmarks.size(); ++i) {
    std::memcpy(set.descriptors.ptr<std::uint8_t>(static_cast<int>(i)), landmarks[i]->descriptor.data(), 32);
    set.keypoints.emplace_back(0.f, 0.f, 7.f);
    // Exhaustive matching skips reference features without depth; every landmark has a
    // position, so each gets a placeholder in front of the camera.
    set.points.emplace_back(0, 0, 1);
  }
  return set;
}

/// The most often re-observed first (the furniture that held the pose longest), at most
/// `max` of them; `hits` reads an element's count.
template <class T, class Hits>
void keepMostReobserved(std::vector<T>& landmarks, int max, Hits hits) {
  std::stable_sort(landmarks.begin(), landmarks.end(), [&](const T& a, const T& b) { return hits(a) > hits(b); });
  if (landmarks.size() > static_cast<size_t>(max)) landmarks.resize(static_cast<size_t>(max));
}

}  // namespace

bool MapRejoin::freeze(int map, std::vector<Landmark> landmarks, double stamp, std::optional<MapAnchor> anchor) {
  if (!options_.young_map_anchor) anchor.reset();
  if (!options_.enabled || (landmarks.size() < static_cast<size_t>(options_.min_inliers) && !anchor)) return false;
  // Full: the oldest map is the frame the trajectory started in; the newest are the
  // likeliest to be seen again. One of each stays when there is room for two.
  if (static_cast<int>(waiting_.size()) >= options_.max_maps) {
    if (options_.max_maps < 2) return false;
    waiting_.erase(waiting_.begin() + 1);
  }
  keepMostReobserved(landmarks, options_.max_landmarks, [](const Landmark& l) { return l.hits_in_place; });
  WaitingMap w;
  w.id = map;
  w.frozen = std::move(landmarks);
  std::vector<const Landmark*> frozen;
  for (const auto& l : w.frozen) frozen.push_back(&l);
  w.frozen_set = descriptorSet(frozen);
  w.frozen_at = stamp;
  w.anchor = std::move(anchor);
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
                                              RejoinAttempt* report, int only, const LandmarkMap* current,
                                              double stamp) {
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
  std::optional<Isometry> found = correction(frontend, map, cur, T_world_cur, camera, r);
  if (map.anchor && current) {
    RejoinAttempt by_anchor = r;
    const std::optional<Isometry> anchored = anchorCorrection(frontend, *map.anchor, *current, stamp, camera, by_anchor);
    if (anchored && (!found || by_anchor.inliers > r.inliers)) {
      found = anchored;
      r = by_anchor;
    }
  }
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
  const std::optional<Isometry> T_cur_old = fitCorrection(c, camera, r);
  if (!T_cur_old) return std::nullopt;
  return T_cur_old->inverse() * T_world_cur.inverse();
}

std::optional<Isometry> MapRejoin::anchorCorrection(const features::Frontend& frontend, const MapAnchor& anchor,
                                                    const LandmarkMap& current, double stamp,
                                                    const PinholeCamera& camera, RejoinAttempt& r) {
  r.by_anchor = true;
  // The current map's landmarks not seen moving (as the map left froze its own), the most
  // often re-observed first. Those with static evidence alone were measured too: they
  // find crowd 16's anchor 100-150 frames later and nothing more (fifty-fourth round).
  std::vector<const Landmark*> room = current.notSeenMoving(stamp);
  r.matches = 0;
  if (room.size() < static_cast<size_t>(options_.min_inliers)) return std::nullopt;
  keepMostReobserved(room, options_.max_landmarks, [](const Landmark* l) { return l->hits_in_place; });
  // 3-D correspondences: landmark (current world) <- anchor keypoint (its camera frame).
  PointCorrespondences c;
  for (const auto& m : frontend.matchExhaustive(descriptorSet(room), anchor.features))
    if (anchor.features.hasDepth(m.cur)) c.add(room[static_cast<size_t>(m.ref)]->position, anchor.features, m.cur);
  r.matches = c.size();
  const std::optional<Isometry> T_anchor_current = fitCorrection(c, camera, r);
  if (!T_anchor_current) return std::nullopt;
  return anchor.T_world_camera * *T_anchor_current;
}

std::optional<Isometry> MapRejoin::fitCorrection(const PointCorrespondences& c, const PinholeCamera& camera,
                                                 RejoinAttempt& r) {
  if (c.size() < options_.min_inliers) return std::nullopt;
  // The pose, refined on the inliers' pixels and depths as any tracked pose.
  const CorrespondenceFit fit = fitCorrespondences(c, c.all(), Isometry::Identity(), options_.ransac_iterations, rng_,
                                                   threshold_, camera, refinement_);
  r.inliers = static_cast<int>(fit.members.size());
  if (r.inliers < options_.min_inliers) return std::nullopt;
  r.inliers = fit.refined.inliers;
  if (fit.refined.inliers < options_.min_inliers) return std::nullopt;
  return fit.refined.T_cur_ref;
}

}  // namespace gmc::vo
