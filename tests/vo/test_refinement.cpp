#include <gtest/gtest.h>

#include <random>

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

TEST(Refinement, TooFewObservationsKeepTheInitialPose) {
  const Isometry init = motion(0.1, 0, 0, 0, 0, 0);
  const auto r = gmc::vo::refinePose({}, init, gmc::PinholeCamera{}, {});
  EXPECT_TRUE(r.T_cur_ref.isApprox(init));
  EXPECT_EQ(r.inliers, 0);
}

}  // namespace
