#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "gmc/vo/window_optimizer.h"

namespace {

using gmc::Isometry;
using gmc::vo::WindowOptimizer;
using gmc::vo::WindowProblem;

Isometry poseAt(int k) {  // a camera sliding sideways and turning slowly, as T_camera_world
  Isometry T_world_camera = Isometry::Identity();
  T_world_camera.translation() = Eigen::Vector3d(0.05 * k, 0.01 * k, 0.0);
  T_world_camera.linear() = Eigen::AngleAxisd(0.02 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return T_world_camera.inverse();
}

double positionError(const Isometry& a, const Isometry& b) {
  return (a.inverse().translation() - b.inverse().translation()).norm();
}

/// Six keyframes of poseAt() over 300 points; every keyframe but the first `exact` starts
/// 2 cm and about 0.6 degrees off, the points `point_noise` m (per axis) off;
/// observations with 0.5 px and Kinect-like depth noise.
struct NoisyWindow {
  WindowProblem truth, problem;
  NoisyWindow(int exact, unsigned seed, double point_noise = 0) {
    const gmc::PinholeCamera camera;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-1.5, 1.5), Z(2.0, 5.0);
    std::normal_distribution<double> N(0, 1);
    for (int k = 0; k < 6; ++k) truth.poses.push_back(poseAt(k));
    for (int j = 0; j < 300; ++j) truth.points.emplace_back(U(rng), 0.6 * U(rng), Z(rng));
    problem = truth;
    if (point_noise > 0)
      for (auto& X : problem.points) X += point_noise * Eigen::Vector3d(N(rng), N(rng), N(rng));
    for (size_t k = static_cast<size_t>(exact); k < truth.poses.size(); ++k) {
      Isometry d = Isometry::Identity();
      d.translation() = 0.02 * Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized();
      d.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d(N(rng), N(rng), N(rng)).normalized()).toRotationMatrix();
      problem.poses[k] = d * truth.poses[k];
    }
    for (int k = 0; k < 6; ++k)
      for (int j = 0; j < 300; ++j) {
        const Eigen::Vector3d p = truth.poses[static_cast<size_t>(k)] * truth.points[static_cast<size_t>(j)];
        if (p.z() <= 0.1 || !camera.inside(camera.project(p).x(), camera.project(p).y())) continue;
        const double depth = p.z() + (0.002 + 0.002 * p.z() * p.z()) * N(rng);
        problem.observations.push_back({k, j, camera.project(p) + 0.5 * Eigen::Vector2d(N(rng), N(rng)), depth});
      }
  }
  double worstError(size_t from) const {
    double e = 0;
    for (size_t k = from; k < truth.poses.size(); ++k) e = std::max(e, positionError(problem.poses[k], truth.poses[k]));
    return e;
  }
};

TEST(WindowOptimizer, RecoversAKnownTrajectoryFromNoisyStart) {
  const gmc::PinholeCamera camera;
  NoisyWindow w(1, 11, 0.01);
  WindowProblem& problem = w.problem;
  ASSERT_GT(problem.observations.size(), 1000u);
  const double before = w.worstError(1);

  gmc::vo::WindowOptions one_fixed{6, 10, 2};
  one_fixed.fixed_keyframes = 1;
  WindowOptimizer optimizer(one_fixed);
  const auto r = optimizer.optimize(problem, camera);
  const double after = w.worstError(1);
  std::printf("  worst keyframe position error %.4f m -> %.4f m, cost %.0f -> %.0f in %d iterations\n", before,
              after, r.initial_cost, r.final_cost, r.iterations);
  EXPECT_LT(r.final_cost, r.initial_cost);
  EXPECT_LT(after, 0.003);
  EXPECT_TRUE(problem.poses[0].isApprox(w.truth.poses[0])) << "the oldest pose holds the gauge";
}

// The window's gauge and anchor: the oldest keyframes stay where tracking put them (the
// newer ones move towards them, not the other way round).
TEST(WindowOptimizer, FixedKeyframesStayAndAnchorTheNewerOnes) {
  const gmc::PinholeCamera camera;
  NoisyWindow w(2, 21);
  const Isometry first = w.problem.poses[0], second = w.problem.poses[1];
  gmc::vo::WindowOptions options{6, 10, 2};
  options.fixed_keyframes = 2;
  WindowOptimizer(options).optimize(w.problem, camera);
  EXPECT_TRUE(w.problem.poses[0].isApprox(first));
  EXPECT_TRUE(w.problem.poses[1].isApprox(second));
  EXPECT_LT(w.worstError(2), 0.003);
  // As many fixed keyframes as poses: nothing to optimise, nothing moves.
  NoisyWindow all(2, 21);
  const auto before = all.problem.poses;
  options.fixed_keyframes = 6;
  WindowOptimizer(options).optimize(all.problem, camera);
  for (size_t k = 0; k < 6; ++k) EXPECT_TRUE(all.problem.poses[k].isApprox(before[k])) << k;
}

// A look-alike corner matched in a landmark's place recurs, displaced the same way
// (doc/odometry.md, "Static evidence"): Huber only damps such observations and a few
// keyframes' worth of them drag the poses; the chi2 gate removes them halfway.
TEST(WindowOptimizer, TheOutlierGateRemovesWrongAssociationsThatHuberOnlyDamps) {
  const gmc::PinholeCamera camera;
  const auto corrupted = [] {
    NoisyWindow w(1, 33);
    int n = 0;
    for (auto& ob : w.problem.observations)
      if (ob.keyframe >= 3 && ob.landmark % 4 == 0) {  // a quarter of the newer views, 8 px to the right
        ob.pixel.x() += 8.0;
        ++n;
      }
    EXPECT_GT(n, 100);
    return w;
  };
  gmc::vo::WindowOptions options{6, 10, 2};
  options.fixed_keyframes = 1;
  options.outlier_gate = 0;
  NoisyWindow huber_only = corrupted();
  WindowOptimizer(options).optimize(huber_only.problem, camera);
  options.outlier_gate = 2.45;
  NoisyWindow gated = corrupted();
  const auto r = WindowOptimizer(options).optimize(gated.problem, camera);
  std::printf("  worst keyframe position error: Huber only %.4f m, gated %.4f m (%d observations removed)\n",
              huber_only.worstError(1), gated.worstError(1), r.outliers);
  EXPECT_GT(r.outliers, 100);
  EXPECT_LT(gated.worstError(1), 0.004);
  EXPECT_GT(huber_only.worstError(1), 1.5 * gated.worstError(1));
}

TEST(WindowOptimizer, AnOutlierLandmarkDoesNotPullThePoses) {
  const gmc::PinholeCamera camera;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.5, 1.5), Z(2.0, 5.0);
  WindowProblem pb;
  for (int k = 0; k < 4; ++k) pb.poses.push_back(poseAt(k));
  for (int j = 0; j < 200; ++j) pb.points.emplace_back(U(rng), 0.6 * U(rng), Z(rng));
  const WindowProblem truth = pb;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 200; ++j) {
      Eigen::Vector3d p = pb.poses[static_cast<size_t>(k)] * pb.points[static_cast<size_t>(j)];
      if (j < 20 && k == 3) p.x() += 0.15;  // ten percent of the points moved (a walker)
      pb.observations.push_back({k, j, camera.project(p), p.z()});
    }
  WindowOptimizer({4, 10, 2}).optimize(pb, camera);
  for (size_t k = 1; k < 4; ++k) EXPECT_LT(positionError(pb.poses[k], truth.poses[k]), 0.005) << k;
}

// The newest keyframe was just measured against the map; a window result that moves it
// by many of that measurement's standard deviations is discarded (crowd seed 2: 25 cm for
// a pose known to 3.2 mm).
TEST(WindowOptimizer, AShiftFarBeyondTheTrackedPosesUncertaintyIsImplausible) {
  const gmc::Isometry tracked = poseAt(2).inverse();
  const auto moved = [&](double x) {
    gmc::Isometry T = tracked;
    T.translation().x() += x;
    return T;
  };
  const gmc::vo::WindowOptions options;  // max_shift_sigmas 20
  EXPECT_FALSE(gmc::vo::plausibleWindowShift(tracked, moved(0.25), 0.0032, options));
  EXPECT_TRUE(gmc::vo::plausibleWindowShift(tracked, moved(0.05), 0.0032, options));   // 16 sigmas
  EXPECT_FALSE(gmc::vo::plausibleWindowShift(tracked, moved(0.07), 0.0032, options));  // 22 sigmas
  EXPECT_TRUE(gmc::vo::plausibleWindowShift(tracked, moved(0.008), 0.0, options));     // below 1 cm
  gmc::vo::WindowOptions never = options;
  never.max_shift_sigmas = 0;
  EXPECT_TRUE(gmc::vo::plausibleWindowShift(tracked, moved(0.25), 0.0032, never));
}

TEST(WindowSelection, WithoutAPoolTheFixedKeyframesAreTheOnesJustBefore) {
  gmc::vo::WindowOptions options;  // 6 keyframes, 2 fixed
  options.covisible_pool = 0;
  const std::vector<std::vector<int>> few = {{1, 2}, {2, 3}, {3, 4}};
  EXPECT_EQ(gmc::vo::selectWindowKeyframes(few, options), (std::vector<size_t>{0, 1, 2}));
  std::vector<std::vector<int>> many(9, std::vector<int>{1, 2, 3});
  EXPECT_EQ(gmc::vo::selectWindowKeyframes(many, options), (std::vector<size_t>{3, 4, 5, 6, 7, 8}));
}

TEST(WindowSelection, APoolFixesTheKeyframesThatSawTheSamePlace) {
  // A camera that looked at place A (landmarks 0-99), turned to B (100-199) and came back:
  // the moved keyframes see A again, and A's keyframes anchor them, not B's just before.
  gmc::vo::WindowOptions options;
  options.covisible_pool = 20;
  const auto place = [](int first, int count) {
    std::vector<int> ids;
    for (int i = 0; i < count; ++i) ids.push_back(first + i);
    return ids;
  };
  std::vector<std::vector<int>> kept;
  kept.push_back(place(0, 100));   // 0: A
  kept.push_back(place(10, 100));  // 1: A, mostly
  kept.push_back(place(100, 80));  // 2-5: B
  kept.push_back(place(110, 80));
  kept.push_back(place(120, 80));
  kept.push_back(place(130, 80));
  for (int k = 0; k < 4; ++k) kept.push_back(place(5 + 2 * k, 90));  // 6-9: A again, moved
  EXPECT_EQ(gmc::vo::selectWindowKeyframes(kept, options), (std::vector<size_t>{0, 1, 6, 7, 8, 9}));
  // Equally shared: the newer ones.
  std::vector<std::vector<int>> same(10, place(0, 50));
  EXPECT_EQ(gmc::vo::selectWindowKeyframes(same, options), (std::vector<size_t>{4, 5, 6, 7, 8, 9}));
  // Without the pool the same keyframes give the ones just before.
  options.covisible_pool = 0;
  EXPECT_EQ(gmc::vo::selectWindowKeyframes(kept, options), (std::vector<size_t>{4, 5, 6, 7, 8, 9}));
}

}  // namespace
