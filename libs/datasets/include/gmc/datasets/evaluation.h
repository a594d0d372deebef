#pragma once
// Trajectory and mask metrics with the TUM RGB-D benchmark's definitions.
#include <opencv2/core.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "gmc/datasets/tum.h"

namespace gmc::datasets {

struct ErrorStats {
  double rmse = 0, mean = 0, median = 0, max = 0;
  static ErrorStats of(const std::vector<double>& errors);
};

/// Absolute trajectory error (TUM evaluate_ate.py): stamps associated within max_dt,
/// estimate positions aligned to ground truth by a rigid transform (Horn, no scale).
struct AteResult {
  ErrorStats error;                  ///< over position errors (m)
  size_t pairs = 0;
  Isometry alignment = Isometry::Identity();  ///< maps estimate into ground-truth frame
  std::vector<double> stamps;        ///< estimate stamps of the pairs
  std::vector<Eigen::Vector3d> gt_positions, aligned_positions;
  std::vector<double> errors;
  /// Diagnostic, not the TUM figure: the same pairs aligned with a similarity (Umeyama
  /// with scale, evo's --correct_scale). A scale far from 1 with a much smaller
  /// scaled_error says the error is a trajectory too long or too short (depth scale),
  /// not a wrong direction.
  double scale = 1.0;
  ErrorStats scaled_error;
};
AteResult computeAte(const std::vector<StampedPose>& groundtruth,
                     const std::vector<StampedPose>& estimate, double max_dt = 0.02);

/// Relative pose error over a fixed time delta (TUM evaluate_rpe.py, --fixed_delta):
/// pairs (i, j) of estimate poses with t_j the stamp closest to t_i + delta (kept when
/// within delta/2 of it), each matched to the nearest ground-truth stamps.
struct RpeResult {
  ErrorStats translation;            ///< m
  ErrorStats rotation;               ///< deg
  size_t pairs = 0;
  double delta_s = 1.0;              ///< the delta the pairs were taken over (s)
  /// Diagnostic: least-squares ratio of the estimate's turn angle to the ground truth's
  /// over the same pairs. Invariant to a constant camera-to-marker rotation; away from 1
  /// it says the estimate turns too much or too little (focal length, or the estimate).
  double rotation_gain = std::nan("");
};
RpeResult computeRpe(const std::vector<StampedPose>& groundtruth,
                     const std::vector<StampedPose>& estimate, double delta = 1.0);

/// Binary classification counts (dynamic = positive).
struct BinaryScore {
  size_t tp = 0, fp = 0, fn = 0, tn = 0;
  double precision() const { return tp + fp ? static_cast<double>(tp) / (tp + fp) : 1.0; }
  double recall() const { return tp + fn ? static_cast<double>(tp) / (tp + fn) : 1.0; }
  void add(bool predicted, bool truth) {
    if (predicted && truth) ++tp;
    else if (predicted) ++fp;
    else if (truth) ++fn;
    else ++tn;
  }
  BinaryScore& operator+=(const BinaryScore& o) {
    tp += o.tp, fp += o.fp, fn += o.fn, tn += o.tn;
    return *this;
  }
};

/// JSON of both results (keys ate.rmse, ate.median, ate.pairs, rpe.trans_rmse, ...,
/// rpe.delta_s); NaN and infinite values are null.
std::string evaluationJson(const AteResult& ate, const RpeResult& rpe);

/// Top view of ground truth and aligned estimate (plane of largest extent) above the
/// position error over time.
cv::Mat plotTrajectory(const AteResult& ate, const std::string& title);

}  // namespace gmc::datasets
