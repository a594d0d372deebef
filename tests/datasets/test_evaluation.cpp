#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <cstdio>
#include <limits>
#include <random>

#include "gmc/datasets/evaluation.h"
#include "test_data.h"

namespace {

using namespace gmc::datasets;

std::vector<StampedPose> circle(int n, double period) {
  std::vector<StampedPose> t;
  for (int i = 0; i < n; ++i) {
    StampedPose p;
    p.stamp = 100.0 + i / 30.0;
    const double a = 2 * M_PI * i / (30.0 * period);
    p.pose.translation() = Eigen::Vector3d(std::cos(a), std::sin(a), 0.1 * a);
    p.pose.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    t.push_back(p);
  }
  return t;
}

TEST(Ate, ReproducesTheTumBenchmarkOnDynaSlam) {
  GMC_REQUIRE_DATA(dir, "tum_fr3_walking_xyz_reference");
  const auto ate = computeAte(readTumTrajectory(dir + "/groundtruth.txt"),
                              readTumTrajectory(dir + "/dynaslam_trajectory.txt"));
  EXPECT_EQ(ate.pairs, 757u);
  EXPECT_NEAR(ate.error.rmse, 0.016314, 1e-5);
}

TEST(Ate, RigidlyMovedEstimateHasZeroError) {
  const auto gt = circle(200, 4);
  auto est = gt;
  gmc::Isometry T = gmc::Isometry::Identity();
  T.linear() = Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(5, -2, 1);
  for (auto& p : est) p.pose = T * p.pose, p.stamp += 0.005;
  const auto ate = computeAte(gt, est);
  EXPECT_EQ(ate.pairs, 200u);
  EXPECT_LT(ate.error.rmse, 1e-9);
  const auto rpe = computeRpe(gt, est, 1.0);
  EXPECT_GT(rpe.pairs, 100u);
  EXPECT_LT(rpe.translation.rmse, 1e-9);
  EXPECT_LT(rpe.rotation.rmse, 1e-6);
}

TEST(Ate, KnownOffsetGivesKnownError) {
  const auto gt = circle(300, 5);
  auto est = gt;
  // Alternate +-1 cm along z: alignment cannot remove it, RMSE is 1 cm.
  for (size_t i = 0; i < est.size(); ++i) est[i].pose.translation().z() += (i % 2 ? 0.01 : -0.01);
  const auto ate = computeAte(gt, est);
  EXPECT_NEAR(ate.error.rmse, 0.01, 2e-4);
  EXPECT_NEAR(ate.error.median, 0.01, 2e-4);
}

TEST(Ate, ScaledEstimateIsExplainedByTheSimilarityAlignment) {
  const auto gt = circle(300, 5);
  auto est = gt;
  // 3 % too long: rigid alignment leaves an error, the similarity removes it all.
  for (auto& p : est) p.pose.translation() *= 1.03;
  const auto ate = computeAte(gt, est);
  EXPECT_GT(ate.error.rmse, 1e-3);
  EXPECT_NEAR(ate.scale, 1 / 1.03, 1e-9);
  EXPECT_LT(ate.scaled_error.rmse, 1e-9);
}

TEST(Rpe, ConstantDriftPerSecond) {
  const auto gt = circle(301, 1e9);  // (almost) still, 10 s
  auto est = gt;
  for (size_t i = 0; i < est.size(); ++i) est[i].pose.translation().x() += 0.02 * (est[i].stamp - 100.0);
  const auto rpe = computeRpe(gt, est, 1.0);
  EXPECT_NEAR(rpe.translation.rmse, 0.02, 1e-3);  // 2 cm per second
  EXPECT_NEAR(rpe.translation.median, 0.02, 1e-3);
}

TEST(Rpe, RotationGainMeasuresHowMuchTheEstimateTurns) {
  const auto gt = circle(301, 10);  // 36 deg per second about z
  EXPECT_NEAR(computeRpe(gt, gt, 1.0).rotation_gain, 1.0, 1e-9);
  auto est = gt;
  for (auto& p : est) {
    const double a = 2 * M_PI * (p.stamp - 100.0) / 10;  // circle()'s angle
    p.pose.linear() = Eigen::AngleAxisd(1.06 * a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  EXPECT_NEAR(computeRpe(gt, est, 1.0).rotation_gain, 1.06, 1e-3);
}

TEST(Ate, TooFewPairsGiveNoResult) {
  const auto gt = circle(10, 4);
  auto est = gt;
  for (auto& p : est) p.stamp += 1.0;  // no stamp within 0.02 s
  EXPECT_EQ(computeAte(gt, est).pairs, 0u);
}

TEST(Json, HasTheDocumentedKeys) {
  const auto gt = circle(100, 4);
  const std::string j = evaluationJson(computeAte(gt, gt), computeRpe(gt, gt));
  for (const char* key : {"\"ate\"", "\"rmse\"", "\"median\"", "\"pairs\"", "\"rpe\"",
                          "\"trans_rmse\"", "\"rot_rmse\""})
    EXPECT_NE(j.find(key), std::string::npos) << key;
}

// "delta_s" was written as 1.0 whatever delta the RPE used.
TEST(Json, RecordsTheRpeDeltaThatWasUsed) {
  const auto gt = circle(100, 4);
  const auto j = nlohmann::json::parse(evaluationJson(computeAte(gt, gt), computeRpe(gt, gt, 0.5)));
  EXPECT_EQ(j.at("rpe").at("delta_s").get<double>(), 0.5);
  EXPECT_EQ(j.at("ate").at("pairs").get<size_t>(), 100u);
  EXPECT_EQ(j.at("rpe").at("trans_rmse").get<double>(), 0.0);
}

// Where along the run the error lives: one [stamp, error] pair per associated pose.
TEST(Json, ListsEveryPosesErrorWithItsStamp) {
  const auto gt = circle(50, 4);
  auto est = gt;
  est[20].pose.translation().x() += 0.3;  // one pose off
  const AteResult ate = computeAte(gt, est);
  const auto per_pose = nlohmann::json::parse(evaluationJson(ate, computeRpe(gt, est))).at("ate").at("per_pose");
  ASSERT_EQ(per_pose.size(), ate.pairs);
  size_t worst = 0;
  for (size_t i = 0; i < per_pose.size(); ++i) {
    EXPECT_EQ(per_pose[i].at(0).get<double>(), ate.stamps[i]);
    EXPECT_EQ(per_pose[i].at(1).get<double>(), ate.errors[i]);
    if (ate.errors[i] > ate.errors[worst]) worst = i;
  }
  EXPECT_EQ(per_pose[worst].at(0).get<double>(), est[20].stamp);
}

// NaN and infinity have no JSON spelling: they are written as null (documented in
// doc/evaluation.md), so the file stays valid JSON.
TEST(Json, NonFiniteValuesAreNull) {
  AteResult ate;
  ate.error.rmse = std::numeric_limits<double>::quiet_NaN();
  ate.error.max = std::numeric_limits<double>::infinity();
  ate.pairs = 5;
  RpeResult rpe;
  rpe.rotation.median = std::numeric_limits<double>::quiet_NaN();
  const auto j = nlohmann::json::parse(evaluationJson(ate, rpe));  // throws on invalid JSON
  EXPECT_TRUE(j.at("ate").at("rmse").is_null());
  EXPECT_TRUE(j.at("ate").at("max").is_null());
  EXPECT_TRUE(j.at("rpe").at("rot_median").is_null());
  EXPECT_EQ(j.at("ate").at("pairs").get<int>(), 5);
}

TEST(Plot, DrawsBothTrajectoriesAndTheErrorPanel) {
  const auto gt = circle(100, 4);
  auto est = gt;
  for (size_t i = 0; i < est.size(); ++i) est[i].pose.translation().z() += (i % 2 ? 0.05 : -0.05);
  const cv::Mat img = plotTrajectory(computeAte(gt, est), "t");
  ASSERT_EQ(img.type(), CV_8UC3);
  cv::Mat red, dark;
  cv::inRange(img, cv::Scalar(0, 0, 150), cv::Scalar(120, 120, 255), red);    // estimate
  cv::inRange(img, cv::Scalar(0, 0, 0), cv::Scalar(60, 60, 60), dark);        // ground truth, text
  const cv::Rect top(0, 60, img.cols, 560), bottom(0, 650, img.cols, img.rows - 650);
  EXPECT_GT(cv::countNonZero(red(top)), 100);
  EXPECT_GT(cv::countNonZero(dark(top)), 100);
  EXPECT_GT(cv::countNonZero(red(bottom)), 100);  // error over time
}

// Fuzz finding (fuzz_tum_trajectory): a NaN error or stamps too far apart for their
// difference made the plot convert NaN to int (undefined behaviour). Now drawn, off-panel.
TEST(Plot, NonFiniteErrorsAndFarApartStampsAreDrawnWithoutFailing) {
  const auto gt = circle(10, 4);
  AteResult ate = computeAte(gt, gt);
  ASSERT_EQ(ate.errors.size(), 10u);
  ate.errors[3] = std::numeric_limits<double>::quiet_NaN();
  ate.error.max = std::numeric_limits<double>::infinity();
  ate.stamps.front() = -1.7e308;
  ate.stamps.back() = 1.7e308;
  const cv::Mat img = plotTrajectory(ate, "t");
  EXPECT_EQ(img.type(), CV_8UC3);
  EXPECT_FALSE(img.empty());
}

TEST(BonnGroundTruth, MarkerBodyPoseBecomesTheCameraPoseAsPublished) {
  // By hand: T_ros · T_gt · T_ros for a pure translation (1, 2, 3) is the translation
  // T_ros·(1, 2, 3) = (-1, 3, 2) (T_ros is its own inverse); times T_m it adds T_m's
  // translation and takes T_m's rotation.
  gmc::Isometry body = gmc::Isometry::Identity();
  body.translation() = Eigen::Vector3d(1, 2, 3);
  const auto camera = gmc::datasets::bonnBodyToCamera({{5.0, body}});
  ASSERT_EQ(camera.size(), 1u);
  EXPECT_EQ(camera[0].stamp, 5.0);
  EXPECT_LT((camera[0].pose.translation() - Eigen::Vector3d(-1 + 0.0113, 3 - 0.0098, 2 + 0.0111)).norm(), 1e-12);
  // The rotation is the nearest one to the published block: orthonormal, det +1, and the
  // block is that rotation times a symmetric positive-definite stretch (polar decomposition).
  const Eigen::Matrix3d r = camera[0].pose.linear();
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  Eigen::Matrix3d m;
  m << 1.0157, 0.1828, -0.2389, 0.0009, -0.8431, -0.6413, -0.3009, 0.6147, -0.8085;
  const Eigen::Matrix3d stretch = r.transpose() * m;
  EXPECT_LT((stretch - stretch.transpose()).norm(), 1e-9);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(stretch).eigenvalues().minCoeff(), 0.0);
  EXPECT_LT((r - m).norm(), 0.15) << "close to the published block (stretched by up to 6 %)";
}

TEST(BonnGroundTruth, RpeOnTheSharedWindowUsesTheCameraFrame) {
  GMC_REQUIRE_DATA(dir, "bonn_crowd_240_389");
  const auto body = gmc::datasets::readGroundTruth(dir + "/groundtruth.txt", "camera");
  const auto camera = gmc::datasets::readGroundTruth(dir + "/groundtruth.txt", "bonn");
  ASSERT_EQ(body.size(), camera.size());
  // The same motion seen from two frames: relative rotation angles agree, positions move
  // by the ~2 cm lever arm only (after each trajectory's rigid alignment).
  const auto ate = gmc::datasets::computeAte(camera, body);
  EXPECT_LT(ate.error.rmse, 0.03);
  // Relative rotations are the same angles about other axes: compared across the two
  // frames they differ (what made the body-frame RPE meaningless), by several degrees.
  const auto rpe = gmc::datasets::computeRpe(camera, body);
  std::printf("  Bonn window, body vs camera frame: ATE %.4f m, RPE 1 s rotation %.2f deg\n", ate.error.rmse,
              rpe.rotation.rmse);
  EXPECT_GT(rpe.rotation.rmse, 3.0);
  EXPECT_THROW(gmc::datasets::readGroundTruth(dir + "/groundtruth.txt", "body"), std::invalid_argument);
}

}  // namespace
