#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "gmc/apps/eval_app.h"
#include "gmc/datasets/tum.h"
#include "run_app.h"
#include "test_data.h"

namespace {

std::string slurp(const std::string& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int runEval(std::vector<std::string> args) {
  return gmc::testdata::runApp<gmc::apps::EvalApp>("gmc-eval", std::move(args));
}

TEST(EvalApp, ReferenceTrajectoryJsonAndPlot) {
  GMC_REQUIRE_DATA(dir, "tum_fr3_walking_xyz_reference");
  const auto out = gmc::testdata::scratchDir("eval_app");
  ASSERT_EQ(runEval({"--gt", dir + "/groundtruth.txt", "--est", dir + "/dynaslam_trajectory.txt",
                     "--json", out + "/e.json", "--plot", out + "/e.png"}),
            0);
  const std::string json = slurp(out + "/e.json");
  EXPECT_NE(json.find("\"pairs\": 757"), std::string::npos) << json;
  EXPECT_NE(json.find("\"rmse\": 0.01631"), std::string::npos) << json;
  EXPECT_GT(std::filesystem::file_size(out + "/e.png"), 1000u);
}

TEST(EvalApp, BadArgumentsAndFilesFail) {
  EXPECT_EQ(runEval({}), 2);
  EXPECT_EQ(runEval({"--gt", "a"}), 2);
  EXPECT_EQ(runEval({"--gt", "a", "--est", "b", "--bogus", "c"}), 2);
  EXPECT_EQ(runEval({"--gt", "a", "--est", "b", "--gt-frame", "body"}), 2);
  EXPECT_EQ(runEval({"--gt", "/nonexistent/gt.txt", "--est", "/nonexistent/est.txt"}), 1);
  const auto out = gmc::testdata::scratchDir("eval_app_bad");
  std::ofstream(out + "/gt.txt") << "1.0 0 0 0 0 0 0 1\n1.1 0 0 0 0 0 0 1\n1.2 0 0 0 0 0 0 1\n";
  std::ofstream(out + "/est.txt") << "5.0 0 0 0 0 0 0 1\n";
  EXPECT_EQ(runEval({"--gt", out + "/gt.txt", "--est", out + "/est.txt", "--json", out + "/x.json"}), 1);
  EXPECT_FALSE(std::filesystem::exists(out + "/x.json"));
}

// A camera that only slides has no rotation gain to measure: the line says so instead
// of printing nan (the JSON has null).
TEST(EvalApp, RotationGainOfAPathThatDoesNotTurnIsNotANumberButSaidSo) {
  const auto out = gmc::testdata::scratchDir("eval_app_no_turn");
  {
    std::ofstream gt(out + "/gt.txt"), est(out + "/est.txt");
    for (int i = 0; i < 90; ++i) {
      gt << 1.0 + i / 30.0 << " " << 0.01 * i << " 0 0 0 0 0 1\n";
      est << 1.0 + i / 30.0 << " " << 0.0101 * i << " 0 0 0 0 0 1\n";
    }
  }
  testing::internal::CaptureStdout();
  EXPECT_EQ(runEval({"--gt", out + "/gt.txt", "--est", out + "/est.txt", "--json", out + "/e.json"}), 0);
  const std::string printed = testing::internal::GetCapturedStdout();
  EXPECT_NE(printed.find("rotation gain n/a (the ground truth does not turn over 1 s)"), std::string::npos) << printed;
  EXPECT_EQ(printed.find("nan"), std::string::npos) << printed;
  EXPECT_NE(slurp(out + "/e.json").find("\"rotation_gain\": null"), std::string::npos) << slurp(out + "/e.json");
}

// The Bonn window's ground truth converted to the camera frame: an estimate equal to the
// converted poses scores zero with --gt-frame bonn and not without it.
TEST(EvalApp, BonnGroundTruthFrame) {
  GMC_REQUIRE_DATA(dir, "bonn_crowd_240_389");
  const auto out = gmc::testdata::scratchDir("eval_app_bonn");
  gmc::datasets::writeTumTrajectory(out + "/camera.txt",
                                    gmc::datasets::readGroundTruth(dir + "/groundtruth.txt", "bonn"));
  testing::internal::CaptureStdout();
  EXPECT_EQ(runEval({"--gt", dir + "/groundtruth.txt", "--est", out + "/camera.txt", "--gt-frame", "bonn"}), 0);
  EXPECT_EQ(runEval({"--gt", dir + "/groundtruth.txt", "--est", out + "/camera.txt"}), 0);
  const std::string printed = testing::internal::GetCapturedStdout();
  const auto first_rpe = printed.find("rot rmse ");
  ASSERT_NE(first_rpe, std::string::npos) << printed;
  EXPECT_LT(std::stod(printed.substr(first_rpe + 9)), 1e-3) << printed;
  EXPECT_GT(std::stod(printed.substr(printed.find("rot rmse ", first_rpe + 1) + 9)), 3.0) << printed;
}

// --gt-out writes the ground truth as compared: Bonn's marker poses converted to the
// camera, so scripts need no copy of the conversion (scripts/frame_steps.py).
TEST(EvalApp, GroundTruthOutIsTheConvertedGroundTruth) {
  const auto out = gmc::testdata::scratchDir("eval_app_gt_out");
  std::ofstream(out + "/gt.txt") << "1.0 0.1 0.2 0.3 0 0 0 1\n1.1 0.2 0.2 0.3 0.1 0 0 0.99498744\n"
                                    "1.2 0.3 0.1 0.3 0 0.2 0 0.9797959\n1.3 0.4 0.1 0.2 0 0 0.3 0.9539392\n";
  testing::internal::CaptureStdout();
  ASSERT_EQ(runEval({"--gt", out + "/gt.txt", "--est", out + "/gt.txt", "--gt-frame", "bonn", "--gt-out",
                     out + "/camera.txt"}),
            0);
  testing::internal::GetCapturedStdout();
  const auto expected = gmc::datasets::readGroundTruth(out + "/gt.txt", "bonn");
  const auto written = gmc::datasets::readTumTrajectory(out + "/camera.txt");
  ASSERT_EQ(written.size(), expected.size());
  for (size_t i = 0; i < written.size(); ++i) {
    EXPECT_NEAR(written[i].stamp, expected[i].stamp, 1e-6);
    EXPECT_LT((written[i].pose.matrix() - expected[i].pose.matrix()).cwiseAbs().maxCoeff(), 1e-6) << i;
  }
  // The marker frame is not the camera frame: the conversion did something.
  EXPECT_GT((written[1].pose.translation() - Eigen::Vector3d(0.2, 0.2, 0.3)).norm(), 0.01);
}

}  // namespace
