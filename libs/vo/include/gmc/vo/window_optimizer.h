#pragma once
// Windowed optimisation: the poses of the last keyframes and the static landmarks they
// observe, refined jointly on reprojection and depth residuals (Huber, then a chi2 gate),
// the oldest poses held fixed. Gauss-Newton / Levenberg-Marquardt on Eigen with the landmarks eliminated
// by the Schur complement (doc/odometry.md says why not Ceres). No I/O.
#include <algorithm>
#include <vector>

#include "gmc/gmc/types.h"
#include "gmc/vo/pose_refinement.h"

namespace gmc::vo {

/// INI section [Window].
struct WindowOptions {
  int keyframes = 6;          ///< keyframes optimised together (0 = off)
  int iterations = 5;         ///< Levenberg-Marquardt iterations per keyframe
  int min_observations = 2;   ///< a landmark takes part when seen by this many keyframes
  double max_shift_sigmas = 20;  ///< a result moving the newest keyframe farther than this
                                 ///< many of its tracked position's standard deviations
                                 ///< (and 1 cm) is discarded (0 = never)
  int fixed_keyframes = 2;     ///< the oldest keyframes of the window held fixed (the gauge
                               ///< and the anchor of the newer ones; at least 1)
  double outlier_gate = 2.45;  ///< after half the iterations, an observation whose whitened
                               ///< pixel or depth residual exceeds this leaves the problem
                               ///< (sqrt of chi2(2 dof, 95 %) = 5.991; 0 = Huber only)
  int covisible_pool = 40;     ///< keyframes of the map kept, from which the fixed ones are the
                               ///< fixed_keyframes sharing the most landmarks with the moved ones
                               ///< (0 = the keyframes just before the moved ones; twenty-third round)
  bool skip_unheld = true;     ///< a keyframe whose tracked pose rested on landmarks since seen
                               ///< moving (more of them suspect than trusted) takes no part: as a
                               ///< fixed keyframe it would pull the newer ones onto what moved

  template <class V>
  void visit(V& v) {
    v("keyframes", keyframes, 0, 64, "keyframes optimised jointly with their landmarks (0 = off)");
    v("iterations", iterations, 1, 100, "Levenberg-Marquardt iterations per new keyframe");
    v("min_observations", min_observations, 2, 64, "keyframes that must see a landmark for it to take part");
    v("max_shift_sigmas", max_shift_sigmas, 0.0, 1e6,
      "discard a result moving the newest keyframe beyond this many tracking standard deviations (0 = never)");
    v("fixed_keyframes", fixed_keyframes, 1, 64, "oldest keyframes of the window held fixed");
    v("outlier_gate", outlier_gate, 0.0, 1e6,
      "whitened pixel or depth residual beyond which an observation leaves the window halfway (0 = Huber only)");
    v("covisible_pool", covisible_pool, 0, 10000,
      "keyframes kept; the fixed ones are those of them sharing the most landmarks with the moved ones (0 = the "
      "keyframes just before)");
    v("skip_unheld", skip_unheld,
      "a keyframe whose pose rested on landmarks since seen moving takes no part (neither fixed nor moved)");
  }
};

/// A landmark seen from a keyframe at `pixel` with `depth` (0 = none).
struct WindowObservation {
  int keyframe = 0;   ///< index into WindowProblem::poses
  int landmark = 0;   ///< index into WindowProblem::points
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  double depth = 0;
};

struct WindowProblem {
  std::vector<Isometry> poses;              ///< T_camera_world per keyframe, oldest first; the first
                                            ///< WindowOptions::fixed_keyframes are held fixed
  std::vector<Eigen::Vector3d> points;      ///< world positions
  std::vector<WindowObservation> observations;
};

struct WindowResult {
  double initial_cost = 0, final_cost = 0;  ///< final_cost over the observations kept by the gate
  int iterations = 0;
  int outliers = 0;  ///< observations the gate removed
};

/// Whether a window result may replace the newest keyframe's tracked pose: the frame was
/// just measured against the map with position standard deviation `tracked_sigma`; a
/// window that moves it by many times that (and by more than 1 cm) has settled on wrong
/// associations, not corrected drift (doc/odometry.md, third round).
bool plausibleWindowShift(const Isometry& T_world_tracked, const Isometry& T_world_optimized, double tracked_sigma,
                          const WindowOptions& options);

/// The kept keyframes (indices, oldest first) one optimisation takes, given the landmarks
/// each observes (sorted ids, oldest keyframe first): the newest keyframes - fixed_keyframes
/// move; before them, the fixed ones. Without a pool they are the keyframes just before;
/// with one, the older keyframes sharing the most landmarks with the moved ones (ties: the
/// newer), as ORB-SLAM2 anchors its local window on covisible keyframes: a hovering or
/// returning camera is held by the keyframes that saw the same place, not by the last few.
std::vector<size_t> selectWindowKeyframes(const std::vector<std::vector<int>>& landmarks_per_keyframe,
                                          const WindowOptions& options);

class WindowOptimizer {
 public:
  explicit WindowOptimizer(const WindowOptions& options = {}, const RefinementOptions& noise = {})
      : options_(options), noise_(noise) {}
  const WindowOptions& options() const { return options_; }
  /// Poses at the start of a problem that optimize() holds fixed (at least 1: the gauge).
  size_t fixedPoses() const { return static_cast<size_t>(std::max(1, options_.fixed_keyframes)); }
  /// Keyframes worth keeping: the window, or the pool its fixed keyframes are chosen from.
  size_t keptKeyframes() const {
    return static_cast<size_t>(std::max({1, options_.keyframes, options_.covisible_pool}));
  }

  /// Refines the poses after the fixed ones and problem.points in place. Nothing moves
  /// when the window holds no more poses than it fixes.
  WindowResult optimize(WindowProblem& problem, const PinholeCamera& camera) const;

 private:
  WindowOptions options_;
  RefinementOptions noise_;  ///< pixel and depth noise, Huber threshold
};

}  // namespace gmc::vo
