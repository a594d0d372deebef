// gmc-rgbd-mapping on bad input (issue #8): each case runs the real app in-process on a
// short simulated sequence (320x240, no walkers) and checks the exit code, the message and
// the counts in summary.json. The ".bad_input" part of the name joins this file to the
// rgbd_mapping part of test_apps (tests/apps/CMakeLists.txt keys on the name up to the dot).
#include <gtest/gtest.h>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "gmc/apps/rgbd_mapping_app.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/tum.h"
#include "gmc/sim/simulator.h"
#include "run_app.h"
#include "test_data.h"
#include "wrong_class_rawlog.h"

namespace {

namespace fs = std::filesystem;
using gmc::datasets::RgbdFrame;

/// Small, fast scene: 320x240 (fr3 intrinsics halved), slow xyz motion, nobody walking.
gmc::sim::SimOptions smallScene(int frames, double camera_height = 1.4) {
  gmc::sim::SimOptions o;
  o.simulator.frames = frames;
  o.simulator.threads = 2;
  o.camera.fx = 267.7, o.camera.fy = 269.6, o.camera.cx = 160.0, o.camera.cy = 123.8;
  o.camera.width = 320, o.camera.height = 240;
  o.trajectory.style = "xyz";
  o.trajectory.amplitude = 0.1;
  o.trajectory.height = camera_height;
  o.people.walkers = 0;
  return o;
}

std::vector<RgbdFrame> renderFrames(const gmc::sim::SimOptions& options) {
  const gmc::sim::Simulator sim(options);
  std::vector<RgbdFrame> frames;
  for (int i = 0; i < sim.frameCount(); ++i) frames.push_back(sim.renderFrame(i).frame);
  return frames;
}

std::string stampName(double stamp) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", stamp);
  return buf;
}

/// TUM layout (rgb/, depth/, rgb.txt, depth.txt); list stamps may be overridden.
std::string writeTumFolder(const std::string& dir, const std::vector<RgbdFrame>& frames,
                           std::vector<double> list_stamps = {}) {
  fs::create_directories(dir + "/rgb");
  fs::create_directories(dir + "/depth");
  if (list_stamps.empty())
    for (const auto& f : frames) list_stamps.push_back(f.stamp);
  std::ofstream rgb(dir + "/rgb.txt"), depth(dir + "/depth.txt");
  for (size_t i = 0; i < frames.size(); ++i) {
    const std::string name = std::to_string(i) + ".png";
    cv::imwrite(dir + "/rgb/" + name, frames[i].rgb);
    cv::imwrite(dir + "/depth/" + name, frames[i].depth);
    rgb << stampName(list_stamps[i]) << " rgb/" << name << "\n";
    depth << stampName(list_stamps[i]) << " depth/" << name << "\n";
  }
  return dir;
}

std::string writeRawlog(const std::string& path, const std::vector<RgbdFrame>& frames,
                        bool externalize = false) {
  gmc::datasets::RawlogWriter w(path, externalize);
  for (const auto& f : frames) w.write(f);
  w.close();
  return path;
}

struct AppRun {
  int exit_code = -1;
  std::string err;      ///< everything the app wrote to stderr
  std::string summary;  ///< summary.json, empty when not written
  long count(const std::string& key) const {
    std::smatch m;
    if (!std::regex_search(summary, m, std::regex("\"" + key + "\": ([0-9]+)"))) return -1;
    return std::stol(m[1]);
  }
  size_t lines(const std::string& pattern) const {
    std::istringstream in(err);
    size_t n = 0;
    for (std::string line; std::getline(in, line);) n += line.find(pattern) != std::string::npos;
    return n;
  }
};

/// The app on `input` with the small scene's intrinsics; stderr captured.
AppRun runMapping(const std::string& input, const std::string& out, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {GMC_SOURCE_DIR "/config/default.ini", input, "--out", out,
                                   "--set", "Dataset.camera=custom", "--set", "Dataset.fx=267.7",
                                   "--set", "Dataset.fy=269.6", "--set", "Dataset.cx=160",
                                   "--set", "Dataset.cy=123.8"};
  args.insert(args.end(), extra.begin(), extra.end());
  AppRun r;
  testing::internal::CaptureStderr();
  r.exit_code = gmc::testdata::runApp<gmc::apps::RgbdMappingApp>("gmc-rgbd-mapping", args);
  r.err = testing::internal::GetCapturedStderr();
  std::ifstream in(out + "/summary.json");
  std::stringstream s;
  s << in.rdbuf();
  r.summary = s.str();
  return r;
}

bool noOutputs(const std::string& out) {
  for (const char* f : {"trajectory_tum.txt", "map.bt", "summary.json"})
    if (fs::exists(fs::path(out) / f)) return false;
  return true;
}

TEST(RgbdMappingBadInput, RawlogCutMidObjectFailsNamingTheFileWithoutOutputs) {
  const auto root = gmc::testdata::scratchDir("bad_cut");
  const auto good = writeRawlog(root + "/good.rawlog", renderFrames(smallScene(8)));
  const std::string cut = root + "/cut.rawlog";
  fs::copy_file(good, cut);
  fs::resize_file(cut, fs::file_size(good) * 2 / 3);
  const AppRun r = runMapping(cut, root + "/out");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.lines("gmc-rgbd-mapping: error: " + cut + ": object "), 1u) << r.err;
  EXPECT_EQ(r.lines("truncated or corrupt rawlog"), 1u) << r.err;
  EXPECT_TRUE(noOutputs(root + "/out")) << "half-written outputs";
  // The uncut file runs (the cut, not the scene, is the problem).
  EXPECT_EQ(runMapping(good, root + "/out_good").count("frames"), 8);
}

TEST(RgbdMappingBadInput, RawlogOfTheWrongObservationClassIsNamed) {
  const auto root = gmc::testdata::scratchDir("bad_class");
  const std::string path = gmc::testdata::writeWrongClassRawlog(root + "/laser.rawlog");
  const AppRun r = runMapping(path, root + "/out");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.lines("gmc-rgbd-mapping: error: " + path +
                    ": no CObservation3DRangeScan in the rawlog (found mrpt::obs::CObservation2DRangeScan, mrpt::obs::CObservationOdometry)"),
            1u)
      << r.err;
  EXPECT_TRUE(noOutputs(root + "/out"));

  // Other classes between RGB-D observations (odometry, other sensors) are passed over.
  const auto frames = renderFrames(smallScene(5));
  const std::string mixed = root + "/mixed.rawlog";
  {
    mrpt::io::CFileGZOutputStream out(mixed);
    auto archive = mrpt::serialization::archiveFrom(out);
    for (const auto& f : frames) {
      mrpt::obs::CObservationOdometry odo;
      odo.timestamp = mrpt::Clock::fromDouble(f.stamp);
      archive << odo << *gmc::datasets::toObservation(f);
    }
  }
  const AppRun m = runMapping(mixed, root + "/out_mixed", {"--set", "Output.map=false"});
  EXPECT_EQ(m.exit_code, 0) << m.err;
  EXPECT_EQ(m.count("frames"), 5);
  EXPECT_EQ(m.count("skipped"), 0);
}

TEST(RgbdMappingBadInput, MissingExternalizedImageIsSkippedNamedAndCounted) {
  const auto root = gmc::testdata::scratchDir("bad_ext");
  const auto path = writeRawlog(root + "/seq.rawlog", renderFrames(smallScene(8)), true);
  std::vector<fs::path> images;
  for (const auto& e : fs::directory_iterator(root + "/seq_Images")) images.push_back(e.path());
  std::sort(images.begin(), images.end());
  ASSERT_EQ(images.size(), 8u);
  fs::remove(images[4]);
  const AppRun r = runMapping(path, root + "/out", {"--set", "Output.map=false"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.lines("warning: skipping " + path + "#4: external image " + images[4].string() +
                    " is missing"),
            1u)
      << r.err;
  EXPECT_EQ(r.count("skipped"), 1);
  EXPECT_EQ(r.count("frames"), 7);
  // Every image missing: nothing can be processed, which is an error.
  for (const auto& i : images) fs::remove(i);
  const AppRun none = runMapping(path, root + "/out_none", {"--set", "Output.map=false"});
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_EQ(none.lines("no frame could be processed"), 1u) << none.err;
}

// A stamp written twice in rgb.txt and depth.txt (a logging glitch): both lines pair up
// (each list line is used once), both frames are processed in list order, and the
// trajectory holds the stamp twice.
TEST(RgbdMappingBadInput, RepeatedTimestampsInATumFolderAreProcessedInListOrder) {
  const auto root = gmc::testdata::scratchDir("bad_stamps");
  const auto frames = renderFrames(smallScene(10));
  std::vector<double> stamps;
  for (const auto& f : frames) stamps.push_back(f.stamp);
  stamps[5] = stamps[4];
  const auto dir = writeTumFolder(root + "/seq", frames, stamps);
  const AppRun r = runMapping(dir, root + "/out", {"--set", "Output.map=false"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.count("frames"), 10);
  EXPECT_EQ(r.count("skipped"), 0);
  EXPECT_EQ(r.count("lost"), 0) << r.err;
  const auto trajectory = gmc::datasets::readTumTrajectory(root + "/out/trajectory_tum.txt");
  ASSERT_EQ(trajectory.size(), 10u);
  EXPECT_DOUBLE_EQ(trajectory[4].stamp, trajectory[5].stamp);
}

// One black RGB image and one frame without any depth in the middle of a good sequence:
// each is marked lost (named on stderr, counted in summary.json), the pose is predicted,
// and tracking resumes on the next good frame. Four black frames in a row: after three
// lost frames the odometry re-anchors a keyframe at the predicted pose (counted too).
TEST(RgbdMappingBadInput, BlackImageAndZeroDepthFramesAreLostAndCounted) {
  const auto root = gmc::testdata::scratchDir("bad_black");
  auto frames = renderFrames(smallScene(20));
  frames[5].rgb.setTo(cv::Scalar::all(0));
  frames[8].depth.setTo(0);
  for (int i = 12; i < 16; ++i) frames[static_cast<size_t>(i)].rgb.setTo(cv::Scalar::all(0));
  const auto dir = writeTumFolder(root + "/seq", frames);
  const AppRun r = runMapping(dir, root + "/out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.count("frames"), 20);
  EXPECT_EQ(r.lines("frame 5 (rgb/5.png) lost"), 1u) << r.err;
  EXPECT_EQ(r.lines("frame 8 (rgb/8.png) lost"), 1u) << r.err;
  // Frames 12, 13 and 15 are reported lost; 14, the third in a row, is the re-anchored one.
  EXPECT_EQ(r.lines("(rgb/1"), 3u) << r.err;
  EXPECT_EQ(r.count("lost"), 6) << r.err;
  EXPECT_EQ(r.count("reanchored"), 1) << r.err;
  EXPECT_EQ(r.count("tracked"), 14) << r.err;
  EXPECT_TRUE(fs::exists(root + "/out/map.bt"));
}

// The camera jumps 1 m up between frames 7 and 8 (two renderings of the same room spliced):
// no crash, and the wide second matching window plus RANSAC follow the jump: no frame is
// lost and the trajectory steps 1 m up (optical y points down).
TEST(RgbdMappingBadInput, SuddenOneMetreJumpIsFollowed) {
  const auto root = gmc::testdata::scratchDir("bad_jump");
  auto frames = renderFrames(smallScene(16, 1.2));
  const auto high = renderFrames(smallScene(16, 2.2));
  std::copy(high.begin() + 8, high.end(), frames.begin() + 8);
  const auto dir = writeTumFolder(root + "/seq", frames);
  const AppRun r = runMapping(dir, root + "/out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.count("frames"), 16);
  EXPECT_EQ(r.count("lost"), 0) << r.err;
  const auto trajectory = gmc::datasets::readTumTrajectory(root + "/out/trajectory_tum.txt");
  ASSERT_EQ(trajectory.size(), 16u);
  const Eigen::Vector3d step = trajectory[8].pose.translation() - trajectory[7].pose.translation();
  EXPECT_NEAR(step.y(), -1.0, 0.05);
  EXPECT_LT(std::abs(step.x()) + std::abs(step.z()), 0.05);
}

}  // namespace
