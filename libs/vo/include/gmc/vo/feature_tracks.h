#pragma once
// Where each keypoint of the current frame was in the world over the last tracked frames
// it was matched through, frame to frame. A walker slow enough to stay inside GMC's
// interval from one frame to the next moves on over several: the odometry makes the
// landmarks of such tracks start suspect (doc/odometry.md, thirty-second round). No I/O.
#include <array>
#include <vector>

#include "gmc/features/frontend.h"

namespace gmc::vo {

class FeatureTracks {
 public:
  static constexpr int kMaxLength = 16;

  /// length: world positions kept per track (0 = off, at most kMaxLength).
  explicit FeatureTracks(int length = 0);
  bool enabled() const { return length_ > 0; }

  /// The next frame. `matches` link the previous frame's keypoints (ref) to this one's
  /// (cur); each keypoint with depth adds its point in the world at `T_world_camera`.
  /// Unless `continues`, every track starts over: a lost, re-posed or rejoined frame's
  /// pose does not continue the poses before it.
  void extend(const features::FeatureSet& cur, const std::vector<features::FeatureMatch>& matches,
              const Isometry& T_world_camera, bool continues);

  /// How far keypoint i's track moved on in one direction (m): twice the smaller of its
  /// two halves' displacements, 0 when they point apart or the track holds fewer than 3
  /// positions. A corner on a depth edge jumps and comes back, a noisy one jitters; both
  /// stay near 0, while a walker's grows with the track.
  double movedOn(size_t i) const;
  /// Positions held for keypoint i (0 without depth or tracks off).
  int positions(size_t i) const { return i < tracks_.size() ? tracks_[i].count : 0; }

 private:
  struct Track {
    std::array<Eigen::Vector3d, kMaxLength> world;  ///< oldest first
    int count = 0;
  };
  int length_;
  std::vector<Track> tracks_;  ///< per keypoint of the last frame given to extend()
};

}  // namespace gmc::vo
