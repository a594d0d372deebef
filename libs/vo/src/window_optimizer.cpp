#include "gmc/vo/window_optimizer.h"

#include <mrpt/math/geometry.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace gmc::vo {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat63 = Eigen::Matrix<double, 6, 3>;

/// Huber cost of a whitened residual of norm a, and its IRLS weight.
double huberCost(double a, double k) { return a <= k ? a * a : 2 * k * a - k * k; }
double huberWeight(double a, double k) { return a <= k ? 1.0 : k / a; }

/// Whitened residuals of one observation and their Jacobians w.r.t. a left perturbation
/// of T_camera_world and the world point.
struct Linearized {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();  ///< u, v, depth (depth 0 when unused)
  Eigen::Matrix<double, 3, 6> J_pose = Eigen::Matrix<double, 3, 6>::Zero();
  Eigen::Matrix3d J_point = Eigen::Matrix3d::Zero();
  double w_px = 0, w_z = 0, cost = 0;
  bool valid = false;
};

Linearized linearize(const Isometry& T_cw, const Eigen::Vector3d& X, const WindowObservation& ob,
                     const PinholeCamera& camera, const RefinementOptions& noise) {
  Linearized l;
  const Eigen::Vector3d p = T_cw * X;
  if (p.z() <= 1e-3) return l;
  l.valid = true;
  const double iz = 1.0 / p.z(), inv_px = 1.0 / noise.pixel_sigma;
  Eigen::Matrix3d dres_dp = Eigen::Matrix3d::Zero();
  dres_dp.row(0) << camera.fx * iz, 0, -camera.fx * p.x() * iz * iz;
  dres_dp.row(1) << 0, camera.fy * iz, -camera.fy * p.y() * iz * iz;
  dres_dp.topRows<2>() *= inv_px;
  l.r.head<2>() = (camera.project(p) - ob.pixel) * inv_px;
  const double a_px = l.r.head<2>().norm();
  l.w_px = huberWeight(a_px, noise.huber);
  l.cost = huberCost(a_px, noise.huber);
  if (noise.use_depth && ob.depth > 0) {
    const double sigma = noise.depthSigma(ob.depth);
    dres_dp.row(2) << 0, 0, 1.0 / sigma;
    l.r.z() = (p.z() - ob.depth) / sigma;
    l.w_z = huberWeight(std::abs(l.r.z()), noise.huber);
    l.cost += huberCost(std::abs(l.r.z()), noise.huber);
  }
  Eigen::Matrix<double, 3, 6> dp;
  dp.leftCols<3>().setIdentity();
  Eigen::Matrix3d minus_p_cross;
  mrpt::math::skew_symmetric3_neg(p, minus_p_cross);
  dp.rightCols<3>() = minus_p_cross;
  l.J_pose = dres_dp * dp;
  l.J_point = dres_dp * T_cw.linear();
  return l;
}

/// Per observation: 1 while it takes part (the outlier gate sets 0).
using ActiveMask = std::vector<std::uint8_t>;

/// Calls f(observation index, its linearisation) for every observation taking part.
template <class F>
void forEachActive(const WindowProblem& pb, const ActiveMask& active, const std::vector<Isometry>& poses,
                   const std::vector<Eigen::Vector3d>& points, const PinholeCamera& camera,
                   const RefinementOptions& noise, F&& f) {
  for (size_t o = 0; o < pb.observations.size(); ++o) {
    if (!active[o]) continue;
    const auto& ob = pb.observations[o];
    f(o, linearize(poses[static_cast<size_t>(ob.keyframe)], points[static_cast<size_t>(ob.landmark)], ob, camera,
                   noise));
  }
}

double totalCost(const WindowProblem& pb, const ActiveMask& active, const std::vector<Isometry>& poses,
                 const std::vector<Eigen::Vector3d>& points, const PinholeCamera& camera,
                 const RefinementOptions& noise) {
  double c = 0;
  forEachActive(pb, active, poses, points, camera, noise, [&](size_t, const Linearized& l) {
    if (l.valid) c += l.cost;
  });
  return c;
}

/// The normal equations, landmarks kept as 3x3 blocks for the Schur complement.
struct NormalEquations {
  std::vector<Mat6> H_pp;
  std::vector<Vec6> g_p;
  std::vector<Eigen::Matrix3d> H_ll;
  std::vector<Eigen::Vector3d> g_l;
  std::vector<Mat63> H_pl;  ///< per observation
};

NormalEquations buildNormalEquations(const WindowProblem& pb, const ActiveMask& active, const PinholeCamera& camera,
                                     const RefinementOptions& noise) {
  NormalEquations ne;
  ne.H_pp.assign(pb.poses.size(), Mat6::Zero());
  ne.g_p.assign(pb.poses.size(), Vec6::Zero());
  ne.H_ll.assign(pb.points.size(), Eigen::Matrix3d::Zero());
  ne.g_l.assign(pb.points.size(), Eigen::Vector3d::Zero());
  ne.H_pl.assign(pb.observations.size(), Mat63::Zero());
  forEachActive(pb, active, pb.poses, pb.points, camera, noise, [&](size_t o, const Linearized& l) {
    if (!l.valid) return;
    const auto& ob = pb.observations[o];
    const Eigen::Vector3d w(l.w_px, l.w_px, l.w_z);
    const Eigen::Matrix<double, 6, 3> JpT_W = l.J_pose.transpose() * w.asDiagonal();
    const Eigen::Matrix3d JlT_W = l.J_point.transpose() * w.asDiagonal();
    const size_t k = static_cast<size_t>(ob.keyframe), j = static_cast<size_t>(ob.landmark);
    ne.H_pp[k] += JpT_W * l.J_pose;
    ne.g_p[k] += JpT_W * l.r;
    ne.H_ll[j] += JlT_W * l.J_point;
    ne.g_l[j] += JlT_W * l.r;
    ne.H_pl[o] = JpT_W * l.J_point;
  });
  return ne;
}

/// Drops the observations whose whitened pixel pair or depth residual exceeds `gate`:
/// wrong associations (a look-alike corner, a depth-edge flip) that Huber only damps
/// still pull a window of a few keyframes off by centimetres (doc/odometry.md, ninth round).
/// Returns how many it dropped; `kept_cost` is the cost of the others.
int gateOutliers(const WindowProblem& pb, double gate, const PinholeCamera& camera, const RefinementOptions& noise,
                 ActiveMask& active, double& kept_cost) {
  int removed = 0;
  kept_cost = 0;
  forEachActive(pb, active, pb.poses, pb.points, camera, noise, [&](size_t o, const Linearized& l) {
    if (l.valid && l.r.head<2>().norm() <= gate && std::abs(l.r.z()) <= gate) {
      kept_cost += l.cost;
      return;
    }
    active[o] = 0;
    ++removed;
  });
  return removed;
}

}  // namespace

bool plausibleWindowShift(const Isometry& T_world_tracked, const Isometry& T_world_optimized, double tracked_sigma,
                          const WindowOptions& options) {
  if (options.max_shift_sigmas <= 0) return true;
  const double shift = (T_world_optimized.translation() - T_world_tracked.translation()).norm();
  return shift <= std::max(options.max_shift_sigmas * tracked_sigma, 0.01);
}

WindowResult WindowOptimizer::optimize(WindowProblem& pb, const PinholeCamera& camera) const {
  WindowResult result;
  const size_t num_poses = pb.poses.size();
  ActiveMask active(pb.observations.size(), 1);
  result.initial_cost = result.final_cost = totalCost(pb, active, pb.poses, pb.points, camera, noise_);
  const size_t fixed = fixedPoses();
  if (num_poses <= fixed || pb.points.empty()) return result;
  std::vector<std::vector<size_t>> obs_of_point(pb.points.size());
  for (size_t o = 0; o < pb.observations.size(); ++o)
    obs_of_point[static_cast<size_t>(pb.observations[o].landmark)].push_back(o);

  const Eigen::Index n = static_cast<Eigen::Index>(6 * (num_poses - fixed));
  const auto block = [fixed](size_t k) { return static_cast<Eigen::Index>(6 * (k - fixed)); };
  double lambda = 1e-4;
  for (int it = 0; it < options_.iterations; ++it) {
    // ORB-SLAM's two passes in one loop: Huber first, then without what the gate rejects.
    if (options_.outlier_gate > 0 && it == options_.iterations / 2) {
      result.outliers += gateOutliers(pb, options_.outlier_gate, camera, noise_, active, result.final_cost);
    }
    const NormalEquations ne = buildNormalEquations(pb, active, camera, noise_);
    // Reduced camera system S dx = b after eliminating every landmark.
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    for (size_t k = fixed; k < num_poses; ++k) {
      Mat6 H = ne.H_pp[k];
      H.diagonal() *= 1 + lambda;
      S.block<6, 6>(block(k), block(k)) += H;
      b.segment<6>(block(k)) -= ne.g_p[k];
    }
    std::vector<Eigen::Matrix3d> H_ll_inv(pb.points.size());
    for (size_t j = 0; j < pb.points.size(); ++j) {
      Eigen::Matrix3d H = ne.H_ll[j];
      H.diagonal() *= 1 + lambda;
      H.diagonal().array() += 1e-9;
      H_ll_inv[j] = H.inverse();
      for (size_t a : obs_of_point[j]) {
        const size_t ka = static_cast<size_t>(pb.observations[a].keyframe);
        if (ka < fixed) continue;
        const Mat63 A = ne.H_pl[a] * H_ll_inv[j];
        b.segment<6>(block(ka)) += A * ne.g_l[j];
        for (size_t c : obs_of_point[j]) {
          const size_t kc = static_cast<size_t>(pb.observations[c].keyframe);
          if (kc < fixed) continue;
          S.block<6, 6>(block(ka), block(kc)) -= A * ne.H_pl[c].transpose();
        }
      }
    }
    const Eigen::VectorXd dx = S.ldlt().solve(b);
    if (!dx.allFinite()) break;
    // Back-substitution, then accept the step only if the robust cost drops.
    std::vector<Isometry> trial_poses = pb.poses;
    std::vector<Eigen::Vector3d> trial_points = pb.points;
    for (size_t k = fixed; k < num_poses; ++k) trial_poses[k] = expSE3(dx.segment<6>(block(k))) * pb.poses[k];
    for (size_t j = 0; j < pb.points.size(); ++j) {
      Eigen::Vector3d rhs = -ne.g_l[j];
      for (size_t a : obs_of_point[j]) {
        const size_t ka = static_cast<size_t>(pb.observations[a].keyframe);
        if (ka >= fixed) rhs -= ne.H_pl[a].transpose() * dx.segment<6>(block(ka));
      }
      trial_points[j] += H_ll_inv[j] * rhs;
    }
    const double cost = totalCost(pb, active, trial_poses, trial_points, camera, noise_);
    ++result.iterations;
    if (cost < result.final_cost) {
      pb.poses.swap(trial_poses);
      pb.points.swap(trial_points);
      const bool small = result.final_cost - cost < 1e-6 * result.final_cost;
      result.final_cost = cost;
      lambda = std::max(1e-7, lambda * 0.1);
      if (small) break;
    } else {
      lambda *= 10;
    }
  }
  return result;
}

std::vector<size_t> selectWindowKeyframes(const std::vector<std::vector<int>>& landmarks_per_keyframe,
                                          const WindowOptions& options) {
  const size_t kept = landmarks_per_keyframe.size();
  const size_t window = static_cast<size_t>(std::max(1, options.keyframes));
  const size_t fixed = static_cast<size_t>(std::max(1, options.fixed_keyframes));
  std::vector<size_t> chosen;
  if (kept <= window || window <= fixed || options.covisible_pool == 0) {
    for (size_t k = kept - std::min(kept, window); k < kept; ++k) chosen.push_back(k);
    return chosen;
  }
  const size_t first_moved = kept - (window - fixed);
  std::vector<int> moved;
  for (size_t k = first_moved; k < kept; ++k)
    moved.insert(moved.end(), landmarks_per_keyframe[k].begin(), landmarks_per_keyframe[k].end());
  std::sort(moved.begin(), moved.end());
  moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
  std::vector<std::pair<size_t, size_t>> shared;  // (landmarks shared, index), best last
  for (size_t k = 0; k < first_moved; ++k) {
    const auto& own = landmarks_per_keyframe[k];
    size_t n = 0;
    for (size_t i = 0, j = 0; i < own.size() && j < moved.size();) {
      if (own[i] < moved[j]) ++i;
      else if (moved[j] < own[i]) ++j;
      else ++n, ++i, ++j;
    }
    shared.emplace_back(n, k);
  }
  std::sort(shared.begin(), shared.end());
  for (size_t k = 0; k < std::min(fixed, shared.size()); ++k) chosen.push_back(shared[shared.size() - 1 - k].second);
  std::sort(chosen.begin(), chosen.end());
  for (size_t k = first_moved; k < kept; ++k) chosen.push_back(k);
  return chosen;
}

}  // namespace gmc::vo
