#pragma once
// Fixed-lag smoothing of the given-out trajectory: once k more frames have been tracked
// on the same map, a frame's pose is replaced by a local quadratic fit (in time) over the
// 2k + 1 tracked poses around it. The live pose stays causal (the map, the masks and the
// live output use it); the trajectory keeps the smoothed one as a revision. A hovering
// camera's tracked poses scatter by about a centimetre from frame to frame where the
// camera moves a few millimetres (doc/odometry.md, twenty-fourth and twenty-fifth rounds).
// No I/O.
#include <deque>
#include <optional>

#include "gmc/gmc/types.h"
#include "gmc/vo/map_records.h"

namespace gmc::vo {

/// A pose at the middle of `window`, from quadratic least-squares fits in time of its
/// positions and of its rotations (tangent space at the middle pose). `window` holds an
/// odd number (at least 3) of poses with distinct stamps, in order. A path whose position
/// and rotation vector are quadratic in time is returned exactly.
Isometry smoothedMiddlePose(const std::deque<RevisedPose>& window);

class TrajectorySmoother {
 public:
  /// half_window k: tracked frames needed on each side (0 = off: nothing is revised).
  /// max_step_change: a frame whose step from the previous one differs from the step
  /// before by more than this (m, and as many radians of rotation) starts a new run: a
  /// jump the tracking followed (a replayed input, a relocalised camera) is not smoothed
  /// over. A hand-held camera's step changes by millimetres, a tracked pose's scatter by
  /// about a centimetre.
  explicit TrajectorySmoother(int half_window = 0, double max_step_change = 0.1)
      : half_window_(half_window), max_step_change_(max_step_change) {}
  int halfWindow() const { return half_window_; }

  /// Forgets the frames so far: the next one starts a new run (a lost frame, a new or
  /// rejoined map, poses revised otherwise).
  void reset() { window_.clear(); }

  /// A tracked frame continuing the current run (unless it jumps: then it starts a new
  /// one). Returns the smoothed pose of the frame half_window frames back once the run
  /// holds 2 half_window + 1 frames.
  std::optional<RevisedPose> add(const RevisedPose& frame);

 private:
  /// Whether `frame` continues the window's motion (its step differs from the last one
  /// by at most max_step_change_; a run's first step is compared with standing still).
  bool continuesRun(const RevisedPose& frame) const;

  int half_window_ = 0;
  double max_step_change_ = 0.1;
  std::deque<RevisedPose> window_;
};

}  // namespace gmc::vo
