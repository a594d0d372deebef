// gmc-baseline-odometry (OpenCV's odometry for comparisons) on a missing or truncated input
// (issue #8): one line naming the file, exit 1, no trajectory written. The ".robust" part of
// the name joins this file to test_apps with the baseline part linked.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "gmc/apps/baseline_app.h"
#include "gmc/datasets/rawlog.h"
#include "noise_frames.h"
#include "run_app.h"
#include "test_data.h"

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

}  // namespace
