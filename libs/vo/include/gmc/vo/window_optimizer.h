#pragma once
// Windowed optimisation: the poses of the last keyframes and the static landmarks they
// observe, refined jointly on reprojection and depth residuals (Huber), the oldest pose
// held fixed. Gauss-Newton / Levenberg-Marquardt on Eigen with the landmarks eliminated
// by the Schur complement (doc/odometry.md says why not Ceres). No I/O.
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

  template <class V>
  void visit(V& v) {
    v("keyframes", keyframes, 0, 64, "keyframes optimised jointly with their landmarks (0 = off)");
    v("iterations", iterations, 1, 100, "Levenberg-Marquardt iterations per new keyframe");
    v("min_observations", min_observations, 2, 64, "keyframes that must see a landmark for it to take part");
    v("max_shift_sigmas", max_shift_sigmas, 0.0, 1e6,
      "discard a result moving the newest keyframe beyond this many tracking standard deviations (0 = never)");
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
  std::vector<Isometry> poses;              ///< T_camera_world per keyframe; poses[0] is held fixed
  std::vector<Eigen::Vector3d> points;      ///< world positions
  std::vector<WindowObservation> observations;
};

struct WindowResult {
  double initial_cost = 0, final_cost = 0;
  int iterations = 0;
};

/// Whether a window result may replace the newest keyframe's tracked pose: the frame was
/// just measured against the map with position standard deviation `tracked_sigma`; a
/// window that moves it by many times that (and by more than 1 cm) has settled on wrong
/// associations, not corrected drift (doc/odometry.md, third round).
bool plausibleWindowShift(const Isometry& T_world_tracked, const Isometry& T_world_optimized, double tracked_sigma,
                          const WindowOptions& options);

class WindowOptimizer {
 public:
  explicit WindowOptimizer(const WindowOptions& options = {}, const RefinementOptions& noise = {})
      : options_(options), noise_(noise) {}
  const WindowOptions& options() const { return options_; }

  /// Refines problem.poses[1..] and problem.points in place.
  WindowResult optimize(WindowProblem& problem, const PinholeCamera& camera) const;

 private:
  WindowOptions options_;
  RefinementOptions noise_;  ///< pixel and depth noise, Huber threshold
};

}  // namespace gmc::vo
