#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "gmc/apps/tum2rawlog_app.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "run_app.h"
#include "test_data.h"

namespace {

namespace fs = std::filesystem;

int runConvert(std::vector<std::string> args) {
  return gmc::testdata::runApp<gmc::apps::Tum2RawlogApp>("gmc-tum2rawlog", std::move(args));
}

std::string runCommand(const std::string& cmd, int& status) {
  std::string out;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  char buf[512];
  while (p && fgets(buf, sizeof buf, p)) out += buf;
  status = p ? pclose(p) : -1;
  return out;
}

void convertAndCheck(const std::string& dir, const char* preset, size_t expected) {
  const auto out = gmc::testdata::scratchDir(std::string("tum2rawlog_") + preset);
  const std::string rawlog = out + "/seq.rawlog";
  ASSERT_EQ(runConvert({dir, rawlog, "--camera", preset}), 0);
  ASSERT_TRUE(fs::exists(out + "/seq_groundtruth.txt"));
  // The sibling ground truth is the camera's (Bonn's marker body converted): at a frame
  // stamp it is the converted pose interpolated there.
  const auto written = gmc::datasets::readTumTrajectory(out + "/seq_groundtruth.txt");
  const auto camera = gmc::datasets::readGroundTruth(dir + "/groundtruth.txt",
                                                     std::string(preset) == "bonn" ? "bonn" : "camera");
  ASSERT_FALSE(written.empty());
  const auto expected_pose = gmc::datasets::interpolatePose(camera, written.front().stamp);
  ASSERT_TRUE(expected_pose.has_value());
  EXPECT_LT((written.front().pose.translation() - expected_pose->translation()).norm(), 1e-6);
  EXPECT_LT(Eigen::AngleAxisd(written.front().pose.linear().transpose() * expected_pose->linear()).angle(), 1e-6);

  // MRPT's own tool reads it.
  if (fs::exists("/usr/bin/rawlog-edit")) {
    int status = 0;
    const std::string info = runCommand("/usr/bin/rawlog-edit --info -i " + rawlog, status);
    EXPECT_EQ(status, 0) << info;
    EXPECT_NE(info.find("Overall number of objects         : " + std::to_string(expected)),
              std::string::npos)
        << info;
  }
  // Same frames back, depth in metres = PNG value / 5000 at sampled pixels.
  auto src = gmc::datasets::openRgbdSource(rawlog, {});
  const auto depth_list = gmc::datasets::readTumList(dir + "/depth.txt");
  const auto rgb_list = gmc::datasets::readTumList(dir + "/rgb.txt");
  gmc::datasets::RgbdFrame f;
  size_t n = 0;
  while (src->next(f)) {
    // Every RGB frame has a depth partner here; stamps are the RGB stamps to the microsecond.
    if (n < rgb_list.size()) {
      EXPECT_NEAR(f.stamp, rgb_list[n].stamp, 5e-7) << n;
    }
    if (n == 0) {
      // The first RGB frame's depth partner is the nearest depth stamp.
      size_t best = 0;
      for (size_t k = 1; k < depth_list.size(); ++k)
        if (std::abs(depth_list[k].stamp - f.stamp) < std::abs(depth_list[best].stamp - f.stamp)) best = k;
      const cv::Mat png = cv::imread(dir + "/" + depth_list[best].path, cv::IMREAD_ANYDEPTH);
      // Raw values are copied exactly and the units come back as exactly 1/5000.
      for (auto [u, v] : {std::pair{50, 60}, {320, 240}, {600, 450}}) {
        EXPECT_EQ(f.depth.at<std::uint16_t>(v, u), png.at<std::uint16_t>(v, u));
        EXPECT_DOUBLE_EQ(f.depthAt(u, v), png.at<std::uint16_t>(v, u) / 5000.0);
      }
    }
    ++n;
  }
  EXPECT_EQ(n, expected);
  fs::remove_all(out);
}

TEST(Tum2Rawlog, BonnCrowd) {
  GMC_REQUIRE_DATA(dir, "bonn_crowd_240_389");
  convertAndCheck(dir, "bonn", 150);
}

TEST(Tum2Rawlog, TumTeddy) {
  GMC_REQUIRE_DATA(dir, "tum_fr3_teddy_1_100");
  convertAndCheck(dir, "fr3", 100);
}

TEST(Tum2Rawlog, BadArguments) {
  EXPECT_EQ(runConvert({}), 2);
  EXPECT_EQ(runConvert({"a", "b", "--camera"}), 2);
  EXPECT_EQ(runConvert({"a", "b", "--frobnicate"}), 2);
  const auto out = gmc::testdata::scratchDir("tum2rawlog_bad");
  EXPECT_EQ(runConvert({out, out + "/x.rawlog", "--camera", "fr9"}), 2);
  EXPECT_EQ(runConvert({out + "/missing", out + "/x.rawlog"}), 1);
  EXPECT_EQ(runConvert({out, out + "/x.rawlog"}), 1);  // no rgb.txt
  EXPECT_FALSE(fs::exists(out + "/x.rawlog"));
}

TEST(Tum2Rawlog, UnpairedFramesAreNamedAndMissingImagesFail) {
  const auto dir = gmc::testdata::scratchDir("tum2rawlog_unpaired");
  fs::create_directories(dir + "/rgb");
  fs::create_directories(dir + "/depth");
  const cv::Mat rgb(8, 8, CV_8UC3, cv::Scalar(10, 20, 30)), depth(8, 8, CV_16UC1, cv::Scalar(5000));
  cv::imwrite(dir + "/rgb/1.png", rgb);
  cv::imwrite(dir + "/rgb/2.png", rgb);
  cv::imwrite(dir + "/depth/1.png", depth);
  std::ofstream(dir + "/rgb.txt") << "# rgb\n1.000000 rgb/1.png\n2.000000 rgb/2.png\n";
  std::ofstream(dir + "/depth.txt") << "1.005000 depth/1.png\n";

  testing::internal::CaptureStderr();
  EXPECT_EQ(runConvert({dir, dir + "/ok.rawlog", "--camera", "8,8,3.5,3.5"}), 0);
  std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find(dir + "/rgb.txt:3: rgb/2.png has no depth frame within 0.02 s"), std::string::npos)
      << err;
  auto src = gmc::datasets::openRgbdSource(dir + "/ok.rawlog", {});
  gmc::datasets::RgbdFrame f;
  ASSERT_TRUE(src->next(f));
  EXPECT_DOUBLE_EQ(f.depthAt(2, 2), 1.0);
  EXPECT_FALSE(src->next(f));

  fs::remove(dir + "/rgb/1.png");
  testing::internal::CaptureStderr();
  EXPECT_EQ(runConvert({dir, dir + "/missing.rawlog", "--camera", "8,8,3.5,3.5"}), 1);
  err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find(dir + "/rgb/1.png (rgb.txt:2): missing or unreadable image"), std::string::npos)
      << err;
  EXPECT_FALSE(fs::exists(dir + "/missing.rawlog"));
}

}  // namespace
