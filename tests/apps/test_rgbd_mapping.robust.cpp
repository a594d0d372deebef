// The other apps on missing, truncated or corrupt input (issue #8; gmc-rgbd-mapping's own
// cases are in test_rgbd_mapping.bad_input.cpp): one line naming the file (and the line or
// object), exit 1, and no output left behind, temporaries included. The ".robust" part of
// the name joins this file to the rgbd_mapping part of test_apps, which links every app
// whose tests are in this folder.
#include <gtest/gtest.h>

#include <octomap/OcTree.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "gmc/apps/eval_app.h"
#include "gmc/apps/map_export_app.h"
#include "gmc/apps/rawlog_filter_app.h"
#include "gmc/apps/tum2rawlog_app.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/source.h"
#include "noise_frames.h"
#include "run_app.h"
#include "test_data.h"
#include "tum_folder.h"
#include "wrong_class_rawlog.h"

namespace {

namespace fs = std::filesystem;
using gmc::testdata::writeTumFolder;
using gmc::datasets::RgbdFrame;

struct Outcome {
  int exit_code = -1;
  std::string err;
  size_t lines(const std::string& pattern) const {
    std::istringstream in(err);
    size_t n = 0;
    for (std::string line; std::getline(in, line);) n += line.find(pattern) != std::string::npos;
    return n;
  }
};

template <class AppT>
Outcome runCaptured(const char* name, std::vector<std::string> args) {
  Outcome r;
  testing::internal::CaptureStderr();
  r.exit_code = gmc::testdata::runApp<AppT>(name, std::move(args));
  r.err = testing::internal::GetCapturedStderr();
  return r;
}

/// Only `keep` (file names) in `dir`: no output and no temporary was left behind.
void expectOnly(const std::string& dir, const std::set<std::string>& keep) {
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_TRUE(keep.count(e.path().filename().string())) << "left behind: " << e.path();
}

size_t framesIn(const std::string& rawlog) {
  auto source = gmc::datasets::openRgbdSource(rawlog, {});
  RgbdFrame f;
  size_t n = 0;
  while (source->next(f)) ++n;
  return n;
}

/// gmc-rawlog-filter with a chain that keeps every observation (no odometry needed).
Outcome runFilter(const std::string& root, const std::string& input, const std::string& output) {
  std::ofstream(root + "/keep.ini", std::ios::trunc) << "[Filters]\nchain = decimate\n[Decimate]\nkeep_every = 1\n";
  return runCaptured<gmc::apps::RawlogFilterApp>("gmc-rawlog-filter", {root + "/keep.ini", input, output});
}

TEST(AppsRobustness, RawlogFilterRejectsACutOrWrongClassRawlogWithoutOutput) {
  const auto root = gmc::testdata::scratchDir("robust_filter");
  const std::string good = root + "/good.rawlog";
  {
    gmc::datasets::RawlogWriter writer(good);
    for (const auto& f : gmc::testdata::noiseFrames(6)) writer.write(f);
    writer.close();
  }
  fs::create_directories(root + "/out");
  const Outcome ok = runFilter(root, good, root + "/out/good.rawlog");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(framesIn(root + "/out/good.rawlog"), 6u);

  const std::string cut = root + "/cut.rawlog";
  fs::copy_file(good, cut);
  fs::resize_file(cut, fs::file_size(good) / 2);
  const Outcome c = runFilter(root, cut, root + "/out/cut.rawlog");
  EXPECT_EQ(c.exit_code, 1);
  EXPECT_EQ(c.lines("gmc-rawlog-filter: error: " + cut + ": object "), 1u) << c.err;
  EXPECT_EQ(c.lines("truncated or corrupt rawlog"), 1u) << c.err;

  const std::string laser = gmc::testdata::writeWrongClassRawlog(root + "/laser.rawlog");
  const Outcome w = runFilter(root, laser, root + "/out/laser.rawlog");
  EXPECT_EQ(w.exit_code, 1);
  EXPECT_EQ(w.lines("gmc-rawlog-filter: error: " + laser + ": no CObservation3DRangeScan in the rawlog"), 1u)
      << w.err;
  expectOnly(root + "/out", {"good.rawlog"});
}

// One unreadable frame in a good TUM folder: gmc-rawlog-filter skips it with a warning naming
// it and writes the rest.
TEST(AppsRobustness, RawlogFilterSkipsAnUnreadableFrameNamingIt) {
  const auto root = gmc::testdata::scratchDir("robust_filter_frame");
  const auto dir = writeTumFolder(root + "/seq", gmc::testdata::noiseFrames(6));
  cv::imwrite(dir + "/depth/3.png", cv::Mat(48, 64, CV_8UC1, cv::Scalar(9)));
  const Outcome r = runFilter(root, dir, root + "/out.rawlog");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.lines("gmc-rawlog-filter: warning: skipping " + dir +
                    "/depth/3.png (depth.txt:4): depth must be a 16-bit single-channel PNG"),
            1u)
      << r.err;
  EXPECT_EQ(framesIn(root + "/out.rawlog"), 5u);
}

// gmc-tum2rawlog is a converter and must not drop data: a bad list line or an unreadable
// depth image is an error naming it, and no rawlog is written.
TEST(AppsRobustness, Tum2RawlogRejectsABadListLineOrDepthImageWithoutOutput) {
  const auto root = gmc::testdata::scratchDir("robust_tum2rawlog");
  const auto dir = writeTumFolder(root + "/seq", gmc::testdata::noiseFrames(5));
  fs::create_directories(root + "/out");
  const std::vector<std::string> camera = {"--camera", "60,60,31.5,23.5"};
  auto convert = [&](const std::string& out) {
    std::vector<std::string> args = {dir, root + "/out/" + out};
    args.insert(args.end(), camera.begin(), camera.end());
    return runCaptured<gmc::apps::Tum2RawlogApp>("gmc-tum2rawlog", args);
  };
  cv::imwrite(dir + "/depth/2.png", cv::Mat(24, 32, CV_16UC1, cv::Scalar(9)));  // wrong size
  const Outcome size = convert("size.rawlog");
  EXPECT_EQ(size.exit_code, 1);
  EXPECT_EQ(size.lines("gmc-tum2rawlog: error: " + dir + "/depth/2.png (depth.txt:3): depth is 32x24"), 1u)
      << size.err;

  std::ofstream(dir + "/rgb.txt", std::ios::app) << "100.500000\n";  // a stamp without a file
  const Outcome list = convert("list.rawlog");
  EXPECT_EQ(list.exit_code, 1);
  EXPECT_EQ(list.lines("gmc-tum2rawlog: error: " + dir + "/rgb.txt:6: "), 1u) << list.err;
  expectOnly(root + "/out", {});
}

// gmc-eval: a malformed trajectory line is named with its file and line; no JSON or plot.
TEST(AppsRobustness, EvalNamesAMalformedTrajectoryLineWithoutOutputs) {
  const auto root = gmc::testdata::scratchDir("robust_eval");
  std::ofstream(root + "/gt.txt") << "1.0 0 0 0 0 0 0 1\n1.1 0.1 0 0 0 0 0 1\n1.2 0.2 0 0 0 0 0 1\n";
  std::ofstream(root + "/est.txt") << "1.0 0 0 0 0 0 0 1\n1.1 0.1 0 0 0 0 0\n1.2 0.2 0 0 0 0 0 1\n";
  fs::create_directories(root + "/out");
  const Outcome r = runCaptured<gmc::apps::EvalApp>(
      "gmc-eval", {"--gt", root + "/gt.txt", "--est", root + "/est.txt", "--json", root + "/out/ate.json", "--plot",
                   root + "/out/plot.png"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.lines("gmc-eval: error: " + root + "/est.txt:2: "), 1u) << r.err;
  expectOnly(root + "/out", {});
}

// gmc-map-export: a map.bt cut in half (a crash while copying it, a full disk) is not a map.
TEST(AppsRobustness, MapExportRejectsATruncatedMapWithoutOutputs) {
  const auto root = gmc::testdata::scratchDir("robust_map");
  octomap::OcTree tree(0.05);
  octomap::Pointcloud cloud;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) cloud.push_back(-1.0f + 0.05f * i, 2.0f, 0.05f * j);
  tree.insertPointCloud(cloud, octomap::point3d(0, 0, 1));
  const std::string map = root + "/map.bt", cut = root + "/cut.bt";
  ASSERT_TRUE(tree.writeBinary(map));
  fs::copy_file(map, cut);
  fs::resize_file(cut, fs::file_size(map) / 2);
  fs::create_directories(root + "/out");
  auto exportPly = [&](const std::string& in, const std::string& ply) {
    return runCaptured<gmc::apps::MapExportApp>("gmc-map-export", {in, "--ply", root + "/out/" + ply});
  };
  ASSERT_EQ(exportPly(map, "map.ply").exit_code, 0);
  const Outcome r = exportPly(cut, "cut.ply");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.lines("gmc-map-export: error: " + cut + ": "), 1u) << r.err;
  expectOnly(root + "/out", {"map.ply"});
}

}  // namespace
