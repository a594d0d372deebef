#pragma once
// Robust Gauss-Newton refinement of a camera motion on reprojection and depth
// residuals (Huber), used on the matches GMC labels static.
#include <cstdint>
#include <vector>

#include "gmc/gmc/types.h"

namespace gmc::vo {
class DepthAlignment;
}

namespace gmc::vo {

/// INI section [Refinement].
struct RefinementOptions {
  int iterations = 10;
  double pixel_sigma = 1.0;        ///< px, keypoint position noise
  double depth_sigma_base = 0.002;  ///< m, depth noise at 0 m ...
  double depth_sigma_per_m2 = 0.002;  ///< ... plus this times z^2 (Kinect-like)
  /// The depth noise at range z (m).
  double depthSigma(double z) const { return depth_sigma_base + depth_sigma_per_m2 * z * z; }
  double huber = 2.0;              ///< Huber threshold on whitened residuals
  bool use_depth = true;           ///< add the depth residual to the reprojection residual

  template <class V>
  void visit(V& v) {
    v("iterations", iterations, 1, 1000, "Gauss-Newton iterations");
    v("pixel_sigma", pixel_sigma, 1e-3, 100.0, "px, keypoint noise");
    v("depth_sigma_base", depth_sigma_base, 1e-5, 1.0, "m, depth noise at zero range");
    v("depth_sigma_per_m2", depth_sigma_per_m2, 0.0, 1.0, "depth noise growth per z^2");
    v("huber", huber, 0.1, 100.0, "Huber threshold on whitened residuals");
    v("use_depth", use_depth, "use the depth residual as well");
  }
};

/// A reference 3-D point observed in the current image at `pixel` with `depth` (0 = none).
struct PointObservation {
  Eigen::Vector3d point_ref;
  Eigen::Vector2d pixel;
  double depth = 0;
  double weight = 1.0;  ///< trust in the point (static evidence), scales its residuals' weight
};

struct RefinementResult {
  Isometry T_cur_ref = Isometry::Identity();
  int inliers = 0;            ///< observations with whitened error below the Huber threshold
  std::vector<std::uint8_t> inlier_flags;  ///< per observation: 1 where counted in `inliers`
  double final_cost = 0;
  bool converged = false;
  /// Medians over the observations at the result: reprojection error (px) and depth
  /// error (m). Next to pixel_sigma and the depth noise model they show whether a
  /// sensor's noise is the one assumed (doc/odometry.md, sixth round).
  double median_pixel_error = 0;
  double median_depth_error = 0;
  /// Information (whitened Gauss-Newton Hessian, Huber-weighted) at the result; its
  /// inverse is the motion's covariance, twist order (translation, rotation).
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
};

/// Exponential of a twist (rho, phi): the isometry of a left perturbation, shared by the
/// frame refinement and the windowed optimisation.
Isometry expSE3(const Eigen::Matrix<double, 6, 1>& xi);

/// The same pose with its rotation re-orthonormalised: poses are inverted (as
/// transposes) and composed with the velocity every frame, which doubles any departure
/// from a rotation each frame until it shows.
Isometry orthonormalized(const Isometry& T);

/// Standard deviation (m) of the current camera's position along its least constrained
/// direction, from the result's information (infinite-like when there is none). Large
/// when the points leave translation and rotation free to trade off, e.g. a narrow strip
/// of one wall under a narrow field of view.
double positionStdDev(const RefinementResult& result);

/// A Gaussian prior on T_cur_ref (the constant-velocity prediction): standard deviations
/// of a left perturbation's translation (m) and rotation (rad); 0 = no prior.
struct MotionPrior {
  Isometry T_cur_ref = Isometry::Identity();
  double sigma_translation = 0;
  double sigma_rotation = 0;
};

/// Refines T_cur_ref (maps reference points into the current camera frame). The prior,
/// when given, joins the cost but not `information` (which measures what the points
/// determine); so does the dense depth term, when given (T_cur_ref is then T_cur_world).
RefinementResult refinePose(const std::vector<PointObservation>& observations,
                            const Isometry& T_cur_ref_initial, const PinholeCamera& camera,
                            const RefinementOptions& options, const MotionPrior& prior = {},
                            const DepthAlignment* dense = nullptr);

}  // namespace gmc::vo
