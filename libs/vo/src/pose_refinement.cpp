#include "gmc/vo/pose_refinement.h"

#include "gmc/vo/depth_alignment.h"

#include <mrpt/math/geometry.h>
#include <mrpt/poses/Lie/SO.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace gmc::vo {
namespace {

inline double huberWeight(double whitened, double k) {
  const double a = std::abs(whitened);
  return a <= k ? 1.0 : k / a;
}

double median(std::vector<double>& values) {
  if (values.empty()) return 0;
  auto mid = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

/// The median reprojection (px) and depth (m) errors of the observations at T_cur_ref.
void medianErrors(const std::vector<PointObservation>& observations, const PinholeCamera& camera,
                  RefinementResult& result) {
  std::vector<double> pixel, depth;
  for (const auto& ob : observations) {
    const Eigen::Vector3d p = result.T_cur_ref * ob.point_ref;
    if (p.z() <= 1e-3) continue;
    pixel.push_back((camera.project(p) - ob.pixel).norm());
    if (ob.depth > 0) depth.push_back(std::abs(p.z() - ob.depth));
  }
  result.median_pixel_error = median(pixel);
  result.median_depth_error = median(depth);
}

}  // namespace

/// exp map of a twist (rho, phi) to an isometry (left perturbation): MRPT's SO(3)
/// exponential for the rotation; the translation is V rho, V the SO(3) left Jacobian
/// (MRPT's SE<3>::exp is a pseudo-exponential that leaves rho as it is).
Isometry expSE3(const Eigen::Matrix<double, 6, 1>& xi) {
  const Eigen::Vector3d rho = xi.head<3>(), phi = xi.tail<3>();
  const double theta = phi.norm();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity(), V = Eigen::Matrix3d::Identity();
  if (theta > 1e-10) {
    const Eigen::Matrix3d K = mrpt::math::skew_symmetric3(Eigen::Vector3d(phi / theta)).asEigen();
    R = mrpt::poses::Lie::SO<3>::exp(mrpt::math::CVectorFixedDouble<3>(phi)).asEigen();
    V += (1 - std::cos(theta)) / theta * K + (theta - std::sin(theta)) / theta * K * K;
  }
  Isometry T = Isometry::Identity();
  T.linear() = R;
  T.translation() = V * rho;
  return T;
}

Isometry orthonormalized(const Isometry& T) {
  Isometry out = Isometry::Identity();
  out.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  out.translation() = T.translation();
  return out;
}

double positionStdDev(const RefinementResult& result) {
  // For a left perturbation (rho, phi) of T_cur_ref the camera centre -R^T t moves by
  // -R^T rho to first order (the phi terms cancel), so the centre's covariance has the
  // eigenvalues of the rho block of the inverse information.
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  const Mat6 regularized = result.information + 1e-9 * Mat6::Identity();  // none: huge, not NaN
  const Eigen::Matrix3d position = regularized.inverse().topLeftCorner<3, 3>();
  const double largest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(position).eigenvalues().maxCoeff();
  return std::isfinite(largest) ? std::sqrt(std::max(0.0, largest)) : HUGE_VAL;
}

RefinementResult refinePose(const std::vector<PointObservation>& observations,
                            const Isometry& T_cur_ref_initial, const PinholeCamera& camera,
                            const RefinementOptions& options, const MotionPrior& prior,
                            const DepthAlignment* dense) {
  RefinementResult result;
  result.T_cur_ref = T_cur_ref_initial;
  if (observations.size() < 3) return result;

  using Vec6 = Eigen::Matrix<double, 6, 1>;
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  for (int it = 0; it < options.iterations; ++it) {
    Mat6 H = Mat6::Zero();
    Vec6 g = Vec6::Zero();
    double cost = 0;
    int inliers = 0;
    result.inlier_flags.assign(observations.size(), 0);
    for (size_t i = 0; i < observations.size(); ++i) {
      const auto& ob = observations[i];
      const Eigen::Vector3d p = result.T_cur_ref * ob.point_ref;
      if (p.z() <= 1e-3) continue;
      const double iz = 1.0 / p.z();
      const double u = camera.fx * p.x() * iz + camera.cx;
      const double v = camera.fy * p.y() * iz + camera.cy;
      // d(point)/d(twist) for a left perturbation: [I | -[p]x] (filled in place: a
      // returned temporary cost 13 % of the refinement)
      Eigen::Matrix<double, 3, 6> dp;
      dp.leftCols<3>().setIdentity();
      mrpt::math::CMatrixDouble33 minus_p_cross;
      mrpt::math::skew_symmetric3_neg(p, minus_p_cross);
      dp.rightCols<3>() = minus_p_cross.asEigen();
      Eigen::Matrix<double, 2, 3> dproj;
      dproj << camera.fx * iz, 0, -camera.fx * p.x() * iz * iz, 0, camera.fy * iz,
          -camera.fy * p.y() * iz * iz;
      const double inv_px = 1.0 / options.pixel_sigma;
      const Eigen::Vector2d r_px = (Eigen::Vector2d(u, v) - ob.pixel) * inv_px;
      const Eigen::Matrix<double, 2, 6> J_px = dproj * dp * inv_px;
      const double w_px = ob.weight * huberWeight(r_px.norm(), options.huber);
      H.noalias() += w_px * J_px.transpose() * J_px;
      g.noalias() += w_px * J_px.transpose() * r_px;
      double sq = r_px.squaredNorm();
      bool inlier = r_px.norm() <= options.huber;
      if (options.use_depth && ob.depth > 0) {
        const double sigma = options.depthSigma(ob.depth);
        const double r_z = (p.z() - ob.depth) / sigma;
        const Eigen::Matrix<double, 1, 6> J_z = dp.row(2) / sigma;
        const double w_z = ob.weight * huberWeight(r_z, options.huber);
        H.noalias() += w_z * J_z.transpose() * J_z;
        g.noalias() += w_z * J_z.transpose() * r_z;
        sq += r_z * r_z;
        inlier = inlier && std::abs(r_z) <= options.huber;
      }
      cost += sq;
      inliers += inlier ? 1 : 0;
      result.inlier_flags[i] = inlier ? 1 : 0;
    }
    result.final_cost = cost;
    result.inliers = inliers;
    result.information = H;
    if (prior.sigma_translation > 0 && prior.sigma_rotation > 0) {
      // r = log(T * T_prior^-1), to first order the left perturbation itself.
      const Isometry D = result.T_cur_ref * prior.T_cur_ref.inverse();
      const Eigen::AngleAxisd aa(D.linear());
      Vec6 r;
      r << D.translation(), aa.angle() * aa.axis();
      Vec6 info;
      info << Eigen::Vector3d::Constant(1.0 / (prior.sigma_translation * prior.sigma_translation)),
          Eigen::Vector3d::Constant(1.0 / (prior.sigma_rotation * prior.sigma_rotation));
      H.diagonal() += info;
      g += info.cwiseProduct(r);
    }
    if (dense) dense->accumulate(result.T_cur_ref, camera, options, H, g);
    H.diagonal().array() += 1e-9;  // keeps degenerate directions solvable
    const Vec6 delta = -H.ldlt().solve(g);
    if (!delta.allFinite()) break;
    result.T_cur_ref = expSE3(delta) * result.T_cur_ref;
    if (delta.norm() < 1e-8) {
      result.converged = true;
      break;
    }
  }
  medianErrors(observations, camera, result);
  return result;
}

}  // namespace gmc::vo
