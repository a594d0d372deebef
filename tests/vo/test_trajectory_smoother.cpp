#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "gmc/vo/trajectory_smoother.h"

namespace {

using gmc::Isometry;
using gmc::vo::RevisedPose;
using gmc::vo::TrajectorySmoother;

constexpr double kFps = 30.0;

/// A hovering hand-held camera: position and rotation vector quadratic in time.
Isometry quadraticPath(double t) {
  Isometry T = Isometry::Identity();
  const Eigen::Vector3d w(0.02 * t + 0.05 * t * t, -0.1 * t, 0.01 + 0.03 * t * t);
  T.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.1 * t - 0.2 * t * t, 0.03 * t, 1.0 + 0.05 * t * t);
  return T;
}

/// A camera circling at 0.3 m/s and 20 deg/s (not quadratic: the fit has a small bias).
Isometry circlingPath(double t) {
  Isometry T = Isometry::Identity();
  const double a = 20.0 * M_PI / 180.0 * t;
  T.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.86 * std::sin(a), 0, 0.86 * (1 - std::cos(a)));
  return T;
}

double rotationDeg(const Isometry& a, const Isometry& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

RevisedPose frameAt(long n, const Isometry& T) { return {n, static_cast<double>(n) / kFps, T}; }

TEST(TrajectorySmoother, OffGivesNothing) {
  TrajectorySmoother smoother(0);
  for (long n = 0; n < 20; ++n) EXPECT_TRUE(smoother.add(frameAt(n, quadraticPath(n / kFps))).empty());
}

// The pose k frames back, once 2k + 1 tracked frames are in: a quadratic path is kept
// exactly, so a smooth camera loses nothing.
TEST(TrajectorySmoother, RevisesTheFrameHalfAWindowBackAndKeepsAQuadraticPathExactly) {
  TrajectorySmoother smoother(4);
  for (long n = 0; n < 30; ++n) {
    const auto revised = smoother.add(frameAt(n, quadraticPath(n / kFps)));
    if (n < 8) {
      EXPECT_TRUE(revised.empty()) << "frame " << n;
      continue;
    }
    ASSERT_EQ(revised.size(), 1u) << "frame " << n;
    EXPECT_EQ(revised[0].frame_number, n - 4);
    const Isometry truth = quadraticPath((n - 4) / kFps);
    EXPECT_LT((revised[0].T_world_camera.translation() - truth.translation()).norm(), 1e-9);
    EXPECT_LT(rotationDeg(revised[0].T_world_camera, truth), 1e-7);
  }
}

// Centimetre noise on each tracked pose (a hovering crowd's, doc/odometry.md: 5 mm per
// axis) shrinks to well under half, and no run is broken by it; a turning camera's path
// is not bent by the fit.
TEST(TrajectorySmoother, RemovesFrameToFrameNoiseWithoutBendingATurningPath) {
  std::mt19937 rng(7);
  std::normal_distribution<double> position(0, 0.005), angle(0, 0.3 * M_PI / 180.0);
  TrajectorySmoother smoother(4);
  double raw2 = 0, smooth2 = 0, raw_rot2 = 0, smooth_rot2 = 0;
  int count = 0;
  std::vector<Isometry> given;
  for (long n = 0; n < 300; ++n) {
    Isometry noisy = circlingPath(n / kFps);
    noisy.translation() += Eigen::Vector3d(position(rng), position(rng), position(rng));
    const Eigen::Vector3d w(angle(rng), angle(rng), angle(rng));
    noisy.linear() = noisy.linear() * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    given.push_back(noisy);
    for (const RevisedPose& revised : smoother.add(frameAt(n, noisy))) {
      const Isometry truth = circlingPath(revised.frame_number / kFps);
      raw2 += (given[static_cast<size_t>(revised.frame_number)].translation() - truth.translation()).squaredNorm();
      smooth2 += (revised.T_world_camera.translation() - truth.translation()).squaredNorm();
      raw_rot2 += std::pow(rotationDeg(given[static_cast<size_t>(revised.frame_number)], truth), 2);
      smooth_rot2 += std::pow(rotationDeg(revised.T_world_camera, truth), 2);
      ++count;
    }
  }
  ASSERT_EQ(count, 292);
  EXPECT_LT(std::sqrt(smooth2 / count), 0.5 * std::sqrt(raw2 / count));
  EXPECT_LT(std::sqrt(smooth_rot2 / count), 0.6 * std::sqrt(raw_rot2 / count));
  // Without noise the circle's fit error is far below the noise removed.
  TrajectorySmoother exact(4);
  for (long n = 0; n < 20; ++n) {
    for (const RevisedPose& r : exact.add(frameAt(n, circlingPath(n / kFps)))) {
      EXPECT_LT((r.T_world_camera.translation() - circlingPath(r.frame_number / kFps).translation()).norm(), 1e-4);
    }
  }
}

// A break in the run (lost frame, new or rejoined map) starts it again: no fit spans it.
TEST(TrajectorySmoother, ARunStartsAgainAfterAReset) {
  TrajectorySmoother smoother(2);
  for (long n = 0; n < 4; ++n) EXPECT_TRUE(smoother.add(frameAt(n, quadraticPath(n / kFps))).empty());
  smoother.reset();
  for (long n = 10; n < 14; ++n) EXPECT_TRUE(smoother.add(frameAt(n, quadraticPath(n / kFps))).empty()) << n;
  const auto revised = smoother.add(frameAt(14, quadraticPath(14 / kFps)));
  ASSERT_EQ(revised.size(), 1u);
  EXPECT_EQ(revised[0].frame_number, 12);
}

// A jump the tracking followed (a replayed input, a relocalised camera) is not smoothed
// over: the frames on either side keep their own motion.
TEST(TrajectorySmoother, AJumpStartsANewRun) {
  TrajectorySmoother smoother(2, 0.1);
  std::vector<RevisedPose> revised;
  for (long n = 0; n < 12; ++n) {
    Isometry T = Isometry::Identity();
    T.translation() = Eigen::Vector3d(0.01 * static_cast<double>(n), n >= 6 ? -1.0 : 0.0, 0);
    for (const RevisedPose& r : smoother.add(frameAt(n, T))) revised.push_back(r);
  }
  // Frames 2-3 (run 0-5) and 8-9 (run 6-11), each exactly on its own straight line.
  ASSERT_EQ(revised.size(), 4u);
  EXPECT_EQ(revised[0].frame_number, 2);
  EXPECT_EQ(revised[1].frame_number, 3);
  EXPECT_EQ(revised[2].frame_number, 8);
  EXPECT_EQ(revised[3].frame_number, 9);
  for (const auto& r : revised) {
    const double y = r.frame_number >= 6 ? -1.0 : 0.0;
    EXPECT_NEAR(r.T_world_camera.translation().y(), y, 1e-9) << r.frame_number;
    EXPECT_NEAR(r.T_world_camera.translation().x(), 0.01 * static_cast<double>(r.frame_number), 1e-9);
  }
}

// With fit_edges, a run's first and last frames are fitted over its first and last full
// window: every frame of a run of at least 2k + 1 is revised once, in order, a quadratic
// path exactly, and frame-to-frame noise at the ends shrinks too.
TEST(TrajectorySmoother, FitsARunsEdgesOverItsFirstAndLastFullWindow) {
  TrajectorySmoother smoother(2, 0.1, true);
  std::vector<RevisedPose> revised;
  for (long n = 0; n < 8; ++n)
    for (const RevisedPose& r : smoother.add(frameAt(n, quadraticPath(n / kFps)))) revised.push_back(r);
  for (const RevisedPose& r : smoother.endRun()) revised.push_back(r);
  ASSERT_EQ(revised.size(), 8u);
  for (size_t i = 0; i < revised.size(); ++i) {
    EXPECT_EQ(revised[i].frame_number, static_cast<long>(i));
    const Isometry truth = quadraticPath(static_cast<double>(i) / kFps);
    EXPECT_LT((revised[i].T_world_camera.translation() - truth.translation()).norm(), 1e-9);
    EXPECT_LT(rotationDeg(revised[i].T_world_camera, truth), 1e-7);
  }
  // A run shorter than a full window keeps its poses; a reset discards without fitting.
  for (long n = 20; n < 24; ++n) EXPECT_TRUE(smoother.add(frameAt(n, quadraticPath(n / kFps))).empty());
  EXPECT_TRUE(smoother.endRun().empty());
  for (long n = 30; n < 36; ++n) smoother.add(frameAt(n, quadraticPath(n / kFps)));
  smoother.reset();
  EXPECT_TRUE(smoother.endRun().empty());

  // Noise: the end frames' error shrinks (less than at the centre, more than nothing).
  std::mt19937 rng(3);
  std::normal_distribution<double> position(0, 0.005);
  double raw2 = 0, fitted2 = 0;
  for (int run = 0; run < 200; ++run) {
    TrajectorySmoother edges(4, 1.0, true);
    std::vector<Isometry> given;
    std::vector<RevisedPose> out;
    for (long n = 0; n < 12; ++n) {
      Isometry noisy = circlingPath(n / kFps);
      noisy.translation() += Eigen::Vector3d(position(rng), position(rng), position(rng));
      given.push_back(noisy);
      for (const RevisedPose& r : edges.add(frameAt(n, noisy))) out.push_back(r);
    }
    for (const RevisedPose& r : edges.endRun()) out.push_back(r);
    ASSERT_EQ(out.size(), 12u);
    for (const RevisedPose& r : out) {
      if (r.frame_number != 0 && r.frame_number != 11) continue;  // the runs' very ends
      const Isometry truth = circlingPath(r.frame_number / kFps);
      raw2 += (given[static_cast<size_t>(r.frame_number)].translation() - truth.translation()).squaredNorm();
      fitted2 += (r.T_world_camera.translation() - truth.translation()).squaredNorm();
    }
  }
  EXPECT_LT(std::sqrt(fitted2), 0.9 * std::sqrt(raw2));
}

}  // namespace
