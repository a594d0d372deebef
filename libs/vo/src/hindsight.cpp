#include "gmc/vo/hindsight.h"

#include <algorithm>
#include <cmath>

namespace gmc::vo {

namespace {

/// A reference FeatureSet of the landmarks in `view` that `keep` selects.
features::FeatureSet subset(const LandmarkView& view, const std::vector<size_t>& keep) {
  features::FeatureSet out;
  out.width = view.set.width;
  out.height = view.set.height;
  out.descriptors.create(static_cast<int>(keep.size()), 32, CV_8UC1);
  for (size_t j = 0; j < keep.size(); ++j) {
    out.keypoints.push_back(view.set.keypoints[keep[j]]);
    out.points.push_back(view.set.points[keep[j]]);
    view.set.descriptors.row(static_cast<int>(keep[j])).copyTo(out.descriptors.row(static_cast<int>(j)));
  }
  return out;
}

}  // namespace

void HindsightPoser::reset() {
  waiting_.clear();
  passed_.clear();
}

void HindsightPoser::renumber(const std::vector<int>& remap) {
  for (auto* frames : {&waiting_, &passed_})
    for (auto& frame : *frames)
      for (int& id : frame.pose_landmarks)
        if (id >= 0) id = remap[static_cast<size_t>(id)];
}

std::vector<RevisedPose> HindsightPoser::add(HindsightFrame&& frame, const LandmarkMap& map,
                                             const Isometry& T_world_current, const PinholeCamera& camera,
                                             const features::Frontend& frontend, double max_depth) {
  if (!options_.enabled) return {};
  const double stamp = frame.stamp;
  waiting_.push_back(std::move(frame));
  if (static_cast<int>(waiting_.size()) <= options_.lag_frames) return {};
  HindsightFrame past = std::move(waiting_.front());
  waiting_.pop_front();
  // A pose still held by trusted landmarks needs no judgement, nor do the frames before it;
  // a lost frame has none to judge and ends what can be posed back.
  if (past.lost || stillHeld(past, map, stamp)) {
    passed_.clear();
    return {};
  }
  std::vector<int> room;
  const std::optional<Isometry> revised = judge(past, map, T_world_current, camera, frontend, max_depth, stamp, room);
  if (!revised) {
    passed_.push_back(std::move(past));
    if (static_cast<int>(passed_.size()) > options_.lag_frames) passed_.pop_front();
    return {};
  }
  if ((revised->translation() - past.T_world_camera.translation()).norm() < options_.min_shift) {
    passed_.clear();  // near enough: its pose holds, and so do the ones before it
    return {};
  }
  past.T_world_camera = *revised;
  const RevisedPose revision{past.frame_number, past.stamp, *revised};
  std::vector<RevisedPose> out = chainBack(std::move(past), std::move(room), camera, frontend);
  out.push_back(revision);
  return out;
}

bool HindsightPoser::stillHeld(const HindsightFrame& frame, const LandmarkMap& map, double stamp) const {
  // A map's first frame is held by none. Dropped landmarks say nothing: a moving camera
  // leaves most of what it saw, and the map culls what it no longer finds. Seen moving
  // (suspect) is the evidence.
  return !frame.pose_landmarks.empty() && map.stillHold(frame.pose_landmarks, stamp);
}

std::optional<Isometry> HindsightPoser::judge(const HindsightFrame& frame, const LandmarkMap& map,
                                              const Isometry& T_world_current, const PinholeCamera& camera,
                                              const features::Frontend& frontend, double max_depth, double stamp,
                                              std::vector<int>& room) {
  // Today's landmarks in view and not seen moving, those with static evidence first (the
  // matching cost is bounded by max_reference).
  LandmarkView view;
  map.view(T_world_current, camera, max_depth, view);
  std::vector<size_t> keep;
  for (size_t k = 0; k < view.ids.size(); ++k)
    if (map.weight(view.ids[k], stamp) > 0) keep.push_back(k);
  std::stable_sort(keep.begin(), keep.end(), [&](size_t a, size_t b) {
    return map.weight(view.ids[a], stamp) > map.weight(view.ids[b], stamp);
  });
  if (static_cast<int>(keep.size()) > options_.max_reference) keep.resize(static_cast<size_t>(options_.max_reference));
  if (static_cast<int>(keep.size()) < options_.min_inliers) return std::nullopt;
  PointCorrespondences c;
  for (const auto& m : frontend.matchExhaustive(subset(view, keep), frame.features)) {
    if (frame.features.hasDepth(m.cur))
      c.add(map[view.ids[keep[static_cast<size_t>(m.ref)]]].position, frame.features, m.cur);
  }
  if (c.size() < options_.min_inliers) return std::nullopt;
  const Isometry best = fit(c, c.all(), frame.T_world_camera, camera, static_cast<std::uint64_t>(frame.frame_number));
  const std::vector<int> agreeing = c.inPlace(best, c.all(), threshold_);
  const double S = static_cast<double>(agreeing.size());
  const double G = static_cast<double>(c.inPlace(frame.T_world_camera, c.all(), threshold_).size());
  if (S < options_.min_inliers || S < options_.min_gain * G || S - G < options_.min_significance * std::sqrt(S + G))
    return std::nullopt;
  room.clear();
  for (int i : agreeing) room.push_back(c.feature[static_cast<size_t>(i)]);
  return best;
}

std::vector<RevisedPose> HindsightPoser::chainBack(HindsightFrame from, std::vector<int> room,
                                                   const PinholeCamera& camera, const features::Frontend& frontend) {
  std::vector<RevisedPose> out;  // newest first, reversed at the end
  while (!passed_.empty()) {
    HindsightFrame past = std::move(passed_.back());
    passed_.pop_back();
    std::vector<std::uint8_t> in_room(from.features.size(), 0);
    for (int f : room) in_room[static_cast<size_t>(f)] = 1;
    // Every feature of the later frame with depth, at its world position; the pose is
    // chosen on its room alone, whose share of all matches is whatever the walkers leave.
    PointCorrespondences c;
    std::vector<int> pool;
    for (const auto& m : frontend.matchExhaustive(from.features, past.features)) {
      if (!past.features.hasDepth(m.cur) || !from.features.hasDepth(m.ref)) continue;
      if (in_room[static_cast<size_t>(m.ref)]) pool.push_back(c.size());
      c.add(from.T_world_camera * from.features.points[static_cast<size_t>(m.ref)], past.features, m.cur);
    }
    if (static_cast<int>(pool.size()) < options_.chain_min_inliers) break;
    const Isometry best = fit(c, pool, from.T_world_camera, camera, static_cast<std::uint64_t>(past.frame_number));
    const int S = static_cast<int>(c.inPlace(best, pool, threshold_).size());
    const int G = static_cast<int>(c.inPlace(past.T_world_camera, pool, threshold_).size());
    // A frame whose given pose the room already holds needs nothing, nor do those before it.
    if (S < options_.chain_min_inliers || 2 * G >= S) break;
    past.T_world_camera = best;
    out.push_back({past.frame_number, past.stamp, best});
    // Its room: every match in place under its pose (grows back what matching lost).
    room.clear();
    for (int i : c.inPlace(best, c.all(), threshold_)) room.push_back(c.feature[static_cast<size_t>(i)]);
    from = std::move(past);
  }
  passed_.clear();
  std::reverse(out.begin(), out.end());
  return out;
}

Isometry HindsightPoser::fit(const PointCorrespondences& c, const std::vector<int>& pool, const Isometry& fallback,
                             const PinholeCamera& camera, std::uint64_t sample_seed) const {
  // Each judgement samples its own stream (frame number and run seed): the result does not
  // depend on how many judgements came before.
  Xorshift64 rng(Xorshift64::seedFor(0x68696e64 ^ sample_seed, run_seed_));
  const CorrespondenceFit fit =
      fitCorrespondences(c, pool, fallback, options_.ransac_iterations, rng, threshold_, camera, refinement_);
  return orthonormalized(fit.refined.T_cur_ref).inverse();  // T_cur_ref maps the world into the camera
}

}  // namespace gmc::vo
