// gmc-baseline-odometry (OpenCV's odometry for comparisons) on a missing or truncated input
// (issue #8): one line naming the file, exit 1, no trajectory written; one unreadable frame in
// a good sequence is skipped with a warning naming it. The ".robust" part of the name joins
// this file to test_apps with the baseline part linked.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "gmc/apps/baseline_app.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/tum.h"
#include "noise_frames.h"
#include "run_app.h"
#include "test_data.h"
#include "tum_folder.h"

namespace {

namespace fs = std::filesystem;

TEST(BaselineRobustness, MissingOrTruncatedInputFailsNamingItWithoutOutput) {
  const auto root = gmc::testdata::scratchDir("robust_baseline");
  const std::string good = root + "/good.rawlog";
  {
    gmc::datasets::RawlogWriter writer(good);
    for (const auto& f : gmc::testdata::noiseFrames(4, 5)) writer.write(f);
    writer.close();
  }
  const std::string cut = root + "/cut.rawlog";
  fs::copy_file(good, cut);
  fs::resize_file(cut, fs::file_size(good) / 2);
  for (const std::string& input : {root + "/missing.rawlog", cut}) {
    SCOPED_TRACE(input);
    const std::string out = root + "/trajectory.txt";
    testing::internal::CaptureStderr();
    const int code = gmc::testdata::runApp<gmc::apps::BaselineApp>(
        "gmc-baseline-odometry", {input, "--out", out, "--camera", "60,60,31.5,23.5"});
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(code, 1);
    EXPECT_EQ(err.rfind("gmc-baseline-odometry: error: " + input, 0), 0u) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(out));
  }
}

// A frame whose depth image is unreadable (8-bit) in the middle of a good TUM folder: a
// warning naming the file and list line, the frame left out of the trajectory and counted in
// the summary line, exit 0.
TEST(BaselineRobustness, UnreadableFrameMidSequenceIsSkippedNamedAndCounted) {
  const auto root = gmc::testdata::scratchDir("robust_baseline_frame");
  const auto frames = gmc::testdata::noiseFrames(6);
  const auto dir = gmc::testdata::writeTumFolder(root + "/seq", frames);
  cv::imwrite(dir + "/depth/3.png", cv::Mat(48, 64, CV_8UC1, cv::Scalar(9)));
  const std::string out = root + "/trajectory.txt";
  testing::internal::CaptureStderr();
  testing::internal::CaptureStdout();
  const int code = gmc::testdata::runApp<gmc::apps::BaselineApp>(
      "gmc-baseline-odometry", {dir, "--out", out, "--camera", "60,60,31.5,23.5"});
  const std::string log = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  ASSERT_EQ(code, 0) << err;
  EXPECT_EQ(err, "gmc-baseline-odometry: warning: skipping " + dir +
                     "/depth/3.png (depth.txt:4): depth must be a 16-bit single-channel PNG\n");
  EXPECT_NE(log.find(": 5 frames, "), std::string::npos) << log;
  EXPECT_NE(log.find(", 1 unreadable skipped, "), std::string::npos) << log;
  const auto trajectory = gmc::datasets::readTumTrajectory(out);
  ASSERT_EQ(trajectory.size(), 5u);
  for (size_t i = 0; i < trajectory.size(); ++i)
    EXPECT_NEAR(trajectory[i].stamp, frames[i < 3 ? i : i + 1].stamp, 1e-5) << i;  // lists carry 6 decimals
}

}  // namespace
