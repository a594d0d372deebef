#include "gmc/vo/map_records.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace gmc::vo {

Isometry scaledMotion(const Isometry& motion, double fraction) {
  const Eigen::AngleAxisd aa(motion.linear());
  Isometry part = Isometry::Identity();
  part.linear() = Eigen::AngleAxisd(aa.angle() * fraction, aa.axis()).toRotationMatrix();
  part.translation() = motion.translation() * fraction;
  return part;
}

Isometry poseBetween(const RevisedPose& from, const RevisedPose& to, double stamp) {
  const double span = to.stamp - from.stamp;
  const double fraction = span > 0 ? (stamp - from.stamp) / span : 0;
  return from.T_world_camera * scaledMotion(from.T_world_camera.inverse() * to.T_world_camera, fraction);
}

void bridgePoses(const std::vector<std::pair<long, double>>& lost, const RevisedPose& from, const RevisedPose& to,
                 std::vector<RevisedPose>& out) {
  for (const auto& [number, stamp] : lost) out.push_back({number, stamp, poseBetween(from, to, stamp)});
}

MapRecords::MapRecord* MapRecords::find(int map) {
  for (auto& m : maps_)
    if (m.id == map) return &m;
  return nullptr;
}

const MapRecords::MapRecord* MapRecords::find(int map) const {
  for (const auto& m : maps_)
    if (m.id == map) return &m;
  return nullptr;
}

void MapRecords::reanchor(int left, const RevisedPose& last_tracked, int started,
                          std::vector<std::pair<long, double>> lost_between) {
  MapRecord* record = find(left);
  if (!record) {
    // The map left had no record (nothing was waiting): its last tracked frame is all a
    // bridge to the new map needs; its poses never move (a join keeps the older frame).
    maps_.push_back({left, left, -1, {last_tracked}, {}, true});
  } else {
    // Its lost frames at the end lead to the new map: they are that map's lost_before.
    auto& frames = record->frames;
    while (!frames.empty() && frames.back().frame_number > last_tracked.frame_number) frames.pop_back();
  }
  MapRecord next;
  next.id = next.frame = started;
  next.lost_before = std::move(lost_between);
  next.left = left;
  maps_.push_back(std::move(next));
}

void MapRecords::add(const RevisedPose& frame) {
  if (!maps_.empty()) maps_.back().frames.push_back(frame);
}

void MapRecords::revise(const RevisedPose& frame) {
  if (maps_.empty()) return;
  auto& frames = maps_.back().frames;
  // Frame numbers increase: by bisection.
  const auto it = std::lower_bound(frames.begin(), frames.end(), frame.frame_number,
                                   [](const RevisedPose& r, long n) { return r.frame_number < n; });
  if (it != frames.end() && it->frame_number == frame.frame_number) it->T_world_camera = frame.T_world_camera;
}

int MapRecords::frameOf(int map) const {
  const MapRecord* record = find(map);
  return record ? record->frame : map;
}

int MapRecords::currentFrame() const { return maps_.empty() ? 0 : maps_.back().frame; }

int MapRecords::join(int a, int b, const Isometry& T_a_b, std::vector<RevisedPose>& revised) {
  const int frame_a = frameOf(a), frame_b = frameOf(b);
  if (frame_a == frame_b) return frame_a;
  // Map ids increase with time: the smaller frame is the older one, and it stays.
  const int kept = std::min(frame_a, frame_b), moved = std::max(frame_a, frame_b);
  const Isometry T_kept_moved = kept == frame_a ? T_a_b : Isometry(T_a_b.inverse());
  std::vector<RevisedPose> changed;
  for (auto& m : maps_) {
    if (m.frame != moved) continue;
    m.frame = kept;
    for (auto& f : m.frames) {
      f.T_world_camera = T_kept_moved * f.T_world_camera;
      changed.push_back(f);
    }
  }
  // Lost frames between two maps now in one frame lie on the path from the one left to
  // the one started (they become the started map's first frames).
  for (auto& m : maps_) {
    const MapRecord* left = m.bridged ? nullptr : find(m.left);
    if (!left || left->frame != m.frame || left->frames.empty() || m.frames.empty()) continue;
    std::vector<RevisedPose> bridged;
    bridgePoses(m.lost_before, left->frames.back(), m.frames.front(), bridged);
    changed.insert(changed.end(), bridged.begin(), bridged.end());
    m.frames.insert(m.frames.begin(), bridged.begin(), bridged.end());
    m.bridged = true;
  }
  std::stable_sort(changed.begin(), changed.end(),
                   [](const RevisedPose& x, const RevisedPose& y) { return x.frame_number < y.frame_number; });
  revised.insert(revised.end(), changed.begin(), changed.end());
  return kept;
}

void MapRecords::forget(int map) {
  const int frame = frameOf(map);
  maps_.erase(std::remove_if(maps_.begin(), maps_.end(), [&](const MapRecord& m) { return m.frame == frame; }),
              maps_.end());
}

}  // namespace gmc::vo
