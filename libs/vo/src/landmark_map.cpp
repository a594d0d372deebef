#include "gmc/vo/landmark_map.h"

#include <algorithm>
#include <cstring>
#include <numeric>

namespace gmc::vo {
namespace {

/// Puts a landmark where an observation (camera frame, at `stamp`) sees it: its
/// evidence starts over, and the observation is the one its matches are judged by.
void placeAt(Landmark& l, const Eigen::Vector3d& seen, const Eigen::Vector3d& point_cur, double stamp) {
  l.position = seen;
  l.origin_point = point_cur;
  l.origin_stamp = stamp;
  l.evidence_since = l.last_seen_in_place = stamp;
  l.hits_in_place = 1;
}

}  // namespace

size_t LandmarkMap::numAlive() const {
  return static_cast<size_t>(
      std::count_if(landmarks_.begin(), landmarks_.end(), [](const Landmark& l) { return l.alive; }));
}

Evidence LandmarkMap::evidence(int id, double stamp) const {
  const Landmark& l = landmarks_[static_cast<size_t>(id)];
  if (!l.alive || l.known_dynamic || stamp < l.suspect_until) return Evidence::Suspect;
  const bool long_enough = l.last_seen_in_place - l.evidence_since >= options_.static_seconds;
  return long_enough && l.hits_in_place >= options_.static_min_hits ? Evidence::Static : Evidence::Young;
}

double LandmarkMap::weight(int id, double stamp) const {
  switch (evidence(id, stamp)) {
    case Evidence::Suspect: return 0.0;
    case Evidence::Young: return options_.young_weight;
    case Evidence::Static: return 1.0;
  }
  return 0.0;
}

bool LandmarkMap::stillHold(const std::vector<int>& ids, double stamp) const {
  int held = 0, moving = 0;
  for (int id : ids) {
    if (id < 0 || !landmarks_[static_cast<size_t>(id)].alive) continue;
    (weight(id, stamp) > 0 ? held : moving) += 1;
  }
  return moving <= held;
}

void LandmarkMap::view(const Isometry& T_world_camera, const PinholeCamera& camera, double max_depth,
                       LandmarkView& out) const {
  out.ids.clear();
  out.set.keypoints.clear();
  out.set.points.clear();
  out.set.width = camera.width;
  out.set.height = camera.height;
  const Isometry T_camera_world = T_world_camera.inverse();
  const double margin = options_.view_margin_px;
  for (size_t i = 0; i < landmarks_.size(); ++i) {
    const Landmark& l = landmarks_[i];
    if (!l.alive) continue;
    const Eigen::Vector3d p = T_camera_world * l.position;
    if (p.z() <= 0.05 || p.z() > max_depth) continue;
    const Eigen::Vector2d uv = camera.project(p);
    if (uv.x() < -margin || uv.y() < -margin || uv.x() >= camera.width + margin ||
        uv.y() >= camera.height + margin)
      continue;
    out.ids.push_back(static_cast<int>(i));
    out.set.points.push_back(p);
    out.set.keypoints.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()), 7.f);
  }
  out.set.descriptors.create(static_cast<int>(out.ids.size()), 32, CV_8UC1);
  for (size_t k = 0; k < out.ids.size(); ++k)
    std::memcpy(out.set.descriptors.ptr<std::uint8_t>(static_cast<int>(k)),
                landmarks_[static_cast<size_t>(out.ids[k])].descriptor.data(), 32);
}

size_t LandmarkMap::numStatic(double stamp) const {
  size_t n = 0;
  for (size_t i = 0; i < landmarks_.size(); ++i) n += evidence(static_cast<int>(i), stamp) == Evidence::Static ? 1 : 0;
  return n;
}

std::vector<const Landmark*> LandmarkMap::notSeenMoving(double stamp) const {
  std::vector<const Landmark*> out;
  for (size_t i = 0; i < landmarks_.size(); ++i)
    if (evidence(static_cast<int>(i), stamp) != Evidence::Suspect) out.push_back(&landmarks_[i]);
  return out;
}

std::vector<Landmark> LandmarkMap::landmarksNotSeenMoving(double stamp) const {
  std::vector<Landmark> out;
  for (const Landmark* l : notSeenMoving(stamp)) out.push_back(*l);
  return out;
}

void LandmarkMap::transform(const Isometry& T_new_old) {
  for (auto& l : landmarks_) l.position = T_new_old * l.position;
}

void LandmarkMap::adopt(const std::vector<Landmark>& landmarks) {
  landmarks_.insert(landmarks_.end(), landmarks.begin(), landmarks.end());
}

std::vector<std::pair<int, int>> LandmarkMap::addFeatures(const features::FeatureSet& features,
                                          const std::vector<std::uint8_t>& matched,
                                          const std::vector<MotionLabel>& labels,
                                          const Isometry& T_world_camera, double stamp, int keyframe) {
  std::vector<std::pair<int, int>> added;
  for (size_t i = 0; i < features.size(); ++i) {
    if (matched[i] || !features.hasDepth(static_cast<int>(i))) continue;
    Landmark l;
    placeAt(l, T_world_camera * features.points[i], features.points[i], stamp);
    std::memcpy(l.descriptor.data(), features.descriptors.ptr<std::uint8_t>(static_cast<int>(i)), 32);
    l.keyframe = keyframe;
    if (labels[i] == MotionLabel::Dynamic) l.suspect_until = stamp + options_.suspect_seconds;
    added.emplace_back(static_cast<int>(i), static_cast<int>(landmarks_.size()));
    landmarks_.push_back(l);
  }
  return added;
}

void LandmarkMap::observe(const std::vector<LandmarkObservation>& observations,
                          const std::vector<int>& visible, const Isometry& T_world_camera,
                          double stamp, const InPlaceThreshold& threshold) {
  for (int id : visible) ++landmarks_[static_cast<size_t>(id)].visible;
  for (const auto& o : observations) {
    Landmark& l = landmarks_[static_cast<size_t>(o.landmark)];
    if (!l.alive) continue;
    ++l.found;
    const Eigen::Vector3d seen = T_world_camera * o.point_cur;
    const double thr = threshold.at(o.point_cur.z());
    const double moved = (seen - l.position).norm();
    const bool in_band = moved <= options_.in_place_factor * thr;
    const bool dynamic_label = o.label == MotionLabel::Dynamic;
    if (stamp < l.suspect_until) {
      // Followed while suspect, so that a walker keeps being recognised; moving on
      // renews the suspicion.
      if (!in_band) l.suspect_until = stamp + options_.suspect_seconds;
      placeAt(l, seen, o.point_cur, stamp);
      continue;
    }
    if (in_band && !dynamic_label) {
      // Running mean over the first observations averages depth noise, then freezes
      // so that a slowly drifting pose cannot drag the map along.
      if (l.hits_in_place < 10) l.position += (seen - l.position) / (l.hits_in_place + 1.0);
      ++l.hits_in_place;
      l.last_seen_in_place = stamp;
      l.moved_streak = 0;
      continue;
    }
    if (in_band) continue;  // GMC's dynamic label within the noise band: no evidence either way
    // Out of place. GMC's label means it moved: it becomes suspect and follows what it
    // is seen on, so that the walker keeps being recognised. A single jump is often a
    // corner on a depth edge whose reading flips between foreground and background, not
    // worth anything. A displacement beyond moved_factor twice in a row that GMC does not
    // call motion is, on static scenes, mostly a look-alike corner matched in its place
    // (the same wrong match recurs); following it would move the landmark onto another
    // point. The landmark is dropped instead: a walker's corner is re-created (and
    // labelled) at the next keyframe.
    ++l.moved_streak;
    const bool moved_far = moved > options_.moved_factor * thr;
    if (moved_far && l.moved_streak >= 2 && !dynamic_label) {
      l.alive = false;
      continue;
    }
    if (dynamic_label) {
      l.suspect_until = stamp + options_.suspect_seconds;
    } else if (l.moved_streak < 3) {
      continue;
    }
    // Moved, or persistently somewhere else: its evidence was for a place it has left.
    placeAt(l, seen, o.point_cur, stamp);
    l.moved_streak = 0;
  }
}

void LandmarkMap::dropKeyframesAfter(int keyframe) {
  for (auto& l : landmarks_)
    if (l.keyframe > keyframe) l.alive = false;
}

void LandmarkMap::judgeStart(const std::vector<std::pair<int, Eigen::Vector3d>>& consensus,
                             const std::vector<int>& outside, int first_keyframe, double since, double stamp) {
  dropKeyframesAfter(first_keyframe);
  for (const auto& [id, position] : consensus) {
    Landmark& l = landmarks_[static_cast<size_t>(id)];
    l.position = position;
    l.suspect_until = -std::numeric_limits<double>::infinity();
    l.evidence_since = since;
    l.last_seen_in_place = stamp;
    l.moved_streak = 0;
  }
  for (int id : outside) distrust(id, stamp);
}

void LandmarkMap::distrust(int id, double stamp) {
  landmarks_[static_cast<size_t>(id)].suspect_until = stamp + options_.suspect_seconds;
}

std::vector<int> LandmarkMap::cull(double stamp) {
  for (size_t i = 0; i < landmarks_.size(); ++i) {
    Landmark& l = landmarks_[i];
    if (!l.alive || l.visible < options_.cull_after_visible) continue;
    // Static landmarks are not judged by their re-finding rate: behind a crowd they are
    // "visible" for seconds without being found, and they are what holds the pose.
    if (evidence(static_cast<int>(i), stamp) == Evidence::Static) continue;
    if (l.found < options_.cull_found_ratio * l.visible) l.alive = false;
  }
  size_t alive = numAlive();
  if (alive > static_cast<size_t>(options_.max_landmarks)) {
    // Least recently seen in place first.
    std::vector<int> order;
    for (size_t i = 0; i < landmarks_.size(); ++i)
      if (landmarks_[i].alive) order.push_back(static_cast<int>(i));
    const size_t drop = alive - static_cast<size_t>(options_.max_landmarks);
    std::nth_element(order.begin(), order.begin() + static_cast<long>(drop), order.end(), [&](int a, int b) {
      const auto& la = landmarks_[static_cast<size_t>(a)];
      const auto& lb = landmarks_[static_cast<size_t>(b)];
      return la.last_seen_in_place != lb.last_seen_in_place ? la.last_seen_in_place < lb.last_seen_in_place : a < b;
    });
    for (size_t k = 0; k < drop; ++k) landmarks_[static_cast<size_t>(order[k])].alive = false;
    alive -= drop;
  }
  if (landmarks_.size() - alive < alive) return {};
  std::vector<int> remap(landmarks_.size(), -1);
  size_t next = 0;
  for (size_t i = 0; i < landmarks_.size(); ++i) {
    if (!landmarks_[i].alive) continue;
    remap[i] = static_cast<int>(next);
    landmarks_[next++] = landmarks_[i];
  }
  landmarks_.resize(next);
  return remap;
}

}  // namespace gmc::vo
