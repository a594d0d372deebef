#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <random>
#include <vector>

#include "gmc/vo/pose_refinement.h"

namespace {

using gmc::Isometry;
using gmc::vo::PointObservation;

Isometry motion(double tx, double ty, double tz, double rx, double ry, double rz) {
  Isometry T = Isometry::Identity();
  T.linear() = (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(tx, ty, tz);
  return T;
}

std::vector<PointObservation> observe(const Isometry& T_cur_ref, const gmc::PinholeCamera& cam,
                                      int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, cam.width), v(0, cam.height), z(0.8, 5.0);
  std::vector<PointObservation> obs;
  while (static_cast<int>(obs.size()) < n) {
    const Eigen::Vector3d p_ref = cam.unproject(u(rng), v(rng), z(rng));
    const Eigen::Vector3d p_cur = T_cur_ref * p_ref;
    if (p_cur.z() < 0.3) continue;
    const Eigen::Vector2d px = cam.project(p_cur);
    if (!cam.inside(px.x(), px.y())) continue;
    obs.push_back({p_ref, px, p_cur.z()});
  }
  return obs;
}

TEST(Refinement, RecoversKnownMotionExactlyWithoutNoise) {
  gmc::PinholeCamera cam;
  std::mt19937 rng(3);
  const Isometry truth = motion(0.05, -0.02, 0.08, 0.02, -0.03, 0.015);
  const auto obs = observe(truth, cam, 300, rng);
  const auto r = gmc::vo::refinePose(obs, Isometry::Identity(), cam, {});
  EXPECT_LT((r.T_cur_ref.translation() - truth.translation()).norm(), 1e-9);
  EXPECT_LT((r.T_cur_ref.linear() - truth.linear()).norm(), 1e-9);
  EXPECT_EQ(r.inliers, 300);
}

TEST(Refinement, RobustToGrossOutliers) {
  gmc::PinholeCamera cam;
  std::mt19937 rng(5);
  const Isometry truth = motion(-0.03, 0.01, 0.04, -0.01, 0.02, 0.0);
  auto obs = observe(truth, cam, 400, rng);
  std::normal_distribution<double> px(0, 0.7);
  for (auto& o : obs) o.pixel += Eigen::Vector2d(px(rng), px(rng));
  for (size_t i = 0; i < obs.size(); i += 10) obs[i].pixel += Eigen::Vector2d(25, -18);  // 10 %
  const auto r = gmc::vo::refinePose(obs, Isometry::Identity(), cam, {});
  EXPECT_LT((r.T_cur_ref.translation() - truth.translation()).norm(), 3e-3);
  EXPECT_LT(Eigen::AngleAxisd(r.T_cur_ref.linear() * truth.linear().transpose()).angle(), 2e-3);
}

TEST(Refinement, ReportsTheMedianErrorsOfItsObservations) {
  // 2 px per axis: the reprojection error's median is that of a Rayleigh distribution,
  // 2 * 1.177 px; depth noise of 1 cm: the absolute error's median is 0.674 cm.
  gmc::PinholeCamera cam;
  std::mt19937 rng(9);
  const Isometry truth = motion(0.02, 0.01, -0.03, 0.01, 0.0, -0.02);
  auto obs = observe(truth, cam, 2000, rng);
  const auto exact = gmc::vo::refinePose(obs, Isometry::Identity(), cam, {});
  EXPECT_LT(exact.median_pixel_error, 1e-6);
  EXPECT_LT(exact.median_depth_error, 1e-6);
  std::normal_distribution<double> px(0, 2.0), dz(0, 0.01);
  for (auto& o : obs) {
    o.pixel += Eigen::Vector2d(px(rng), px(rng));
    o.depth += dz(rng);
  }
  const auto noisy = gmc::vo::refinePose(obs, Isometry::Identity(), cam, {});
  EXPECT_NEAR(noisy.median_pixel_error, 2 * 1.177, 0.15);
  EXPECT_NEAR(noisy.median_depth_error, 0.00674, 0.0008);
}

TEST(Refinement, TooFewObservationsKeepTheInitialPose) {
  const Isometry init = motion(0.1, 0, 0, 0, 0, 0);
  const auto r = gmc::vo::refinePose({}, init, gmc::PinholeCamera{}, {});
  EXPECT_TRUE(r.T_cur_ref.isApprox(init));
  EXPECT_EQ(r.inliers, 0);
}

/// Observations of `points` (reference frame) seen after `truth`, with the noise the
/// refinement's default options assume: 1 px per axis, depth 2 mm + 2 mm/m^2 z^2.
std::vector<PointObservation> noisyObservations(const std::vector<Eigen::Vector3d>& points, const Isometry& truth,
                                                const gmc::PinholeCamera& cam, std::mt19937& rng) {
  std::normal_distribution<double> unit(0, 1);
  std::vector<PointObservation> obs;
  for (const auto& p_ref : points) {
    const Eigen::Vector3d p_cur = truth * p_ref;
    const double z_sigma = 0.002 + 0.002 * p_cur.z() * p_cur.z();
    obs.push_back({p_ref, cam.project(p_cur) + Eigen::Vector2d(unit(rng), unit(rng)), p_cur.z() + z_sigma * unit(rng)});
  }
  return obs;
}

/// Spread (m) of the estimated camera positions along their widest direction, and the
/// median reported positionStdDev, over repeated noisy draws of the same scene.
std::pair<double, double> positionSpread(const std::vector<Eigen::Vector3d>& points, const Isometry& truth,
                                         const gmc::PinholeCamera& cam, int trials) {
  std::mt19937 rng(11);
  std::vector<Eigen::Vector3d> centres;
  std::vector<double> reported;
  for (int i = 0; i < trials; ++i) {
    const auto r = gmc::vo::refinePose(noisyObservations(points, truth, cam, rng), truth, cam, {});
    centres.push_back(r.T_cur_ref.inverse().translation());
    reported.push_back(gmc::vo::positionStdDev(r));
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& c : centres) mean += c / trials;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& c : centres) cov += (c - mean) * (c - mean).transpose() / (trials - 1);
  std::nth_element(reported.begin(), reported.begin() + trials / 2, reported.end());
  return {std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues().maxCoeff()),
          reported[static_cast<size_t>(trials / 2)]};
}

// positionStdDev is what the odometry's "pose not determined" check reads: it must match
// the actual scatter of the estimated camera position under the assumed noise, both for a
// well spread scene and for a narrow strip of one wall seen through a narrow lens (the
// situation of a walker covering all but the edge of the view), where it is many times
// larger and decimetres wide.
TEST(Refinement, PositionStdDevMatchesTheScatterOfNoisyEstimates) {
  const Isometry truth = motion(0.04, -0.01, 0.03, 0.01, -0.02, 0.03);
  std::mt19937 rng(7);

  gmc::PinholeCamera wide;
  std::vector<Eigen::Vector3d> spread;
  std::uniform_real_distribution<double> u(0, wide.width), v(0, wide.height), z(0.8, 5.0);
  while (spread.size() < 60) spread.push_back(wide.unproject(u(rng), v(rng), z(rng)));

  gmc::PinholeCamera narrow;  // 320 x 240, fx = fy = 600: 30 x 23 degrees
  narrow.fx = narrow.fy = 600, narrow.cx = 160, narrow.cy = 120, narrow.width = 320, narrow.height = 240;
  std::vector<Eigen::Vector3d> strip;  // a 40 px wide strip of a wall 4 m away, left edge
  std::uniform_real_distribution<double> strip_u(5, 45), strip_v(5, 235);
  while (strip.size() < 30) strip.push_back(narrow.unproject(strip_u(rng), strip_v(rng), 4.0));

  const auto [spread_actual, spread_reported] = positionSpread(spread, truth, wide, 300);
  const auto [strip_actual, strip_reported] = positionSpread(strip, truth, narrow, 300);
  std::printf("  position std dev: spread scene %.4f m reported / %.4f m actual; wall strip %.3f / %.3f m\n",
              spread_reported, spread_actual, strip_reported, strip_actual);
  EXPECT_NEAR(spread_reported / spread_actual, 1.0, 0.25);
  EXPECT_NEAR(strip_reported / strip_actual, 1.0, 0.25);
  EXPECT_LT(spread_reported, 0.01);
  EXPECT_GT(strip_reported, 10 * spread_reported);
}

TEST(Refinement, PositionStdDevWithoutObservationsIsHugeNotNan) {
  const auto r = gmc::vo::refinePose({}, Isometry::Identity(), gmc::PinholeCamera{}, {});
  EXPECT_GT(gmc::vo::positionStdDev(r), 1e3);
}

}  // namespace
