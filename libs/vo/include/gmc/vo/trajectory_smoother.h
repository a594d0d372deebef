#pragma once
// Fixed-lag smoothing of the given-out trajectory: once k more frames have been tracked
// on the same map, a frame's pose is replaced by a local quadratic fit (in time) over the
// 2k + 1 tracked poses around it. The live pose stays causal (the map, the masks and the
// live output use it); the trajectory keeps the smoothed one as a revision. A hovering
// camera's tracked poses scatter by about a centimetre from frame to frame where the
// camera moves a few millimetres (doc/odometry.md, twenty-fourth and twenty-fifth rounds).
// A run's first and last frames can be fitted over its first or last full window (the
// fit evaluated off its centre, as Savitzky-Golay filters treat a signal's ends).
// No I/O.
#include <deque>
#include <vector>

#include "gmc/gmc/types.h"
#include "gmc/vo/map_records.h"

namespace gmc::vo {

/// The pose of `window[index]`, from quadratic least-squares fits in time of the window's
/// positions and of its rotations (tangent space at that pose). `window` holds at least 3
/// poses with distinct stamps, in order. A path whose position and rotation vector are
/// quadratic in time is returned exactly.
Isometry smoothedPoseAt(const std::deque<RevisedPose>& window, size_t index);

class TrajectorySmoother {
 public:
  /// half_window k: tracked frames needed on each side (0 = off: nothing is revised).
  /// max_step_change: a frame whose step from the previous one differs from the step
  /// before by more than this (m, and as many radians of rotation) starts a new run: a
  /// jump the tracking followed (a replayed input, a relocalised camera) is not smoothed
  /// over. A hand-held camera's step changes by millimetres, a tracked pose's scatter by
  /// about a centimetre.
  /// fit_edges: a run's first and last half_window frames are fitted too, over the
  /// run's first or last 2 half_window + 1 frames (off: they keep their pose).
  explicit TrajectorySmoother(int half_window = 0, double max_step_change = 0.1, bool fit_edges = false)
      : half_window_(half_window), max_step_change_(max_step_change), fit_edges_(fit_edges) {}
  int halfWindow() const { return half_window_; }

  /// Forgets the frames so far: the next one starts a new run (new or rejoined map, poses
  /// revised otherwise: the run's poses are no longer the ones given out).
  void reset() { window_.clear(); }

  /// Ends the current run whose poses stand (a lost frame follows): with fit_edges, the
  /// fitted poses of its last half_window frames, else nothing. The next frame starts a
  /// new run.
  std::vector<RevisedPose> endRun();

  /// A tracked frame continuing the current run (unless it jumps: then the run before it
  /// ends as in endRun and it starts a new one). Returns the smoothed pose of the frame
  /// half_window frames back once the run holds 2 half_window + 1 frames (with fit_edges,
  /// on that first full window, also those of the run's first half_window frames).
  std::vector<RevisedPose> add(const RevisedPose& frame);

 private:
  /// Whether `frame` continues the window's motion (its step differs from the last one
  /// by at most max_step_change_; a run's first step is compared with standing still).
  bool continuesRun(const RevisedPose& frame) const;

  /// The fitted pose of window_[index], as a revision of that frame.
  RevisedPose fitted(size_t index) const;

  int half_window_ = 0;
  double max_step_change_ = 0.1;
  bool fit_edges_ = false;
  std::deque<RevisedPose> window_;
};

}  // namespace gmc::vo
