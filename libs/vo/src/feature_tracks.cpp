#include "gmc/vo/feature_tracks.h"

#include <algorithm>

namespace gmc::vo {

FeatureTracks::FeatureTracks(int length) : length_(std::clamp(length, 0, kMaxLength)) {}

void FeatureTracks::extend(const features::FeatureSet& cur, const std::vector<features::FeatureMatch>& matches,
                           const Isometry& T_world_camera, bool continues) {
  if (!enabled()) return;
  std::vector<Track> next(cur.size());
  if (continues) {
    for (const auto& m : matches)
      if (static_cast<size_t>(m.ref) < tracks_.size() && static_cast<size_t>(m.cur) < next.size())
        next[static_cast<size_t>(m.cur)] = tracks_[static_cast<size_t>(m.ref)];
  }
  for (size_t i = 0; i < next.size(); ++i) {
    Track& t = next[i];
    if (!cur.hasDepth(static_cast<int>(i))) {
      t.count = 0;  // a track needs every step: a gap would hide where it went
      continue;
    }
    if (t.count == length_) {
      std::move(t.world.begin() + 1, t.world.begin() + length_, t.world.begin());
      --t.count;
    }
    t.world[static_cast<size_t>(t.count++)] = T_world_camera * cur.points[i];
  }
  tracks_.swap(next);
}

double FeatureTracks::movedOn(size_t i) const {
  if (i >= tracks_.size() || tracks_[i].count < 3) return 0;
  const Track& t = tracks_[i];
  const auto half = static_cast<size_t>(t.count / 2);
  const Eigen::Vector3d first = t.world[half] - t.world[0];
  const Eigen::Vector3d second = t.world[static_cast<size_t>(t.count - 1)] - t.world[half];
  if (first.dot(second) <= 0) return 0;
  return 2 * std::min(first.norm(), second.norm());
}

}  // namespace gmc::vo
