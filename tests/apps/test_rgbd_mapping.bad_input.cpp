// gmc-rgbd-mapping on bad input and faults (issue #8): each case runs the real app in-process
// on a short simulated sequence (320x240, no walkers unless the case needs one) and checks
// the exit code, the message and the counts in summary.json; the signal case runs the built
// executable as a child process. The ".bad_input" part of the name joins this file to the
// rgbd_mapping part of test_apps (tests/apps/CMakeLists.txt keys on the name up to the dot).
#include <gtest/gtest.h>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>
#include <octomap/OcTree.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>
#include <utility>

#include "child_process.h"
#include "gmc/apps/rgbd_mapping_app.h"
#include "gmc/datasets/evaluation.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/tum.h"
#include "gmc/sim/simulator.h"
#include "run_app.h"
#include "test_data.h"
#include "tum_folder.h"
#include "wrong_class_rawlog.h"

namespace {

namespace fs = std::filesystem;
using gmc::testdata::writeTumFolder;
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

/// The simulator's camera poses for frames [first, first + count).
std::vector<gmc::datasets::StampedPose> groundTruth(const gmc::sim::SimOptions& options, int first, int count) {
  const gmc::sim::Simulator sim(options);
  std::vector<gmc::datasets::StampedPose> poses;
  for (int i = first; i < first + count; ++i) poses.push_back({sim.stamp(i), sim.cameraPose(i)});
  return poses;
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
  /// Indices of the frames reported lost on stderr ("frame N (name) lost: ...").
  std::vector<int> lostFrames() const {
    std::vector<int> lost;
    const std::regex line("gmc-rgbd-mapping: frame ([0-9]+) \\([^)]*\\) lost");
    for (std::sregex_iterator it(err.begin(), err.end(), line), end; it != end; ++it)
      lost.push_back(std::stoi((*it)[1]));
    return lost;
  }
  size_t lines(const std::string& pattern) const {
    std::istringstream in(err);
    size_t n = 0;
    for (std::string line; std::getline(in, line);) n += line.find(pattern) != std::string::npos;
    return n;
  }
};

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The app with `config` on `input` with the small scene's intrinsics; stderr captured.
AppRun runMappingWith(const std::string& config, const std::string& input, const std::string& out,
                      std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {config, input, "--out", out,
                                   "--set", "Dataset.camera=custom", "--set", "Dataset.fx=267.7",
                                   "--set", "Dataset.fy=269.6", "--set", "Dataset.cx=160",
                                   "--set", "Dataset.cy=123.8"};
  args.insert(args.end(), extra.begin(), extra.end());
  AppRun r;
  testing::internal::CaptureStderr();
  r.exit_code = gmc::testdata::runApp<gmc::apps::RgbdMappingApp>("gmc-rgbd-mapping", args);
  r.err = testing::internal::GetCapturedStderr();
  r.summary = readFile(out + "/summary.json");
  return r;
}

/// The same with config/default.ini.
AppRun runMapping(const std::string& input, const std::string& out, std::vector<std::string> extra = {}) {
  return runMappingWith(GMC_SOURCE_DIR "/config/default.ini", input, out, std::move(extra));
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
  const AppRun r = runMapping(dir, root + "/out", {"--set", "Keyframes.reanchor_after_lost=3"});
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

// Frames that cannot be read in the middle of a good TUM folder (an 8-bit depth PNG, a depth
// PNG of another size, a corrupt RGB PNG, a depth file that is missing): each is skipped
// with one warning naming the file and its list line, counted as skipped; the rest is mapped.
TEST(RgbdMappingBadInput, UnreadableFramesMidSequenceAreSkippedNamedAndCounted) {
  const auto root = gmc::testdata::scratchDir("bad_frames");
  const auto dir = writeTumFolder(root + "/seq", renderFrames(smallScene(16)));
  cv::imwrite(dir + "/depth/3.png", cv::Mat(240, 320, CV_8UC1, cv::Scalar(40)));
  cv::imwrite(dir + "/depth/6.png", cv::Mat(120, 160, CV_16UC1, cv::Scalar(10000)));
  std::ofstream(dir + "/rgb/9.png", std::ios::trunc) << "\x89PNG\r\n\x1a\n garbage";
  fs::remove(dir + "/depth/12.png");
  const AppRun r = runMapping(dir, root + "/out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string skipping = "gmc-rgbd-mapping: warning: skipping " + dir;
  EXPECT_EQ(r.lines(skipping + "/depth/3.png (depth.txt:4): depth must be a 16-bit single-channel PNG"), 1u)
      << r.err;
  EXPECT_EQ(r.lines(skipping + "/depth/6.png (depth.txt:7): depth is 160x120, RGB is 320x240"), 1u) << r.err;
  EXPECT_EQ(r.lines(skipping + "/rgb/9.png (rgb.txt:10): missing or unreadable image"), 1u) << r.err;
  EXPECT_EQ(r.lines(skipping + "/depth/12.png (depth.txt:13): missing or unreadable depth image"), 1u)
      << r.err;
  EXPECT_EQ(r.lines("warning: skipping"), 4u) << r.err;
  EXPECT_EQ(r.count("skipped"), 4);
  EXPECT_EQ(r.count("frames"), 12);
  EXPECT_EQ(r.count("lost"), 0) << r.err;
  EXPECT_EQ(gmc::datasets::readTumTrajectory(root + "/out/trajectory_tum.txt").size(), 12u);
}

// A list line that is no "stamp path" pair (here a stamp without a file name) makes the whole
// input unreadable: one line naming the list file and line, exit 1, nothing written.
TEST(RgbdMappingBadInput, TumListWithABadLineFailsNamingFileAndLineWithoutOutputs) {
  const auto root = gmc::testdata::scratchDir("bad_list");
  const auto dir = writeTumFolder(root + "/seq", renderFrames(smallScene(6)));
  std::string list = readFile(dir + "/depth.txt");
  list.insert(list.find('\n', list.find('\n') + 1) + 1, "1000000000.050000\n");
  std::ofstream(dir + "/depth.txt", std::ios::trunc) << list;
  const AppRun r = runMapping(dir, root + "/out");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.lines("gmc-rgbd-mapping: error: " + dir + "/depth.txt:3: expected 'timestamp filename'"), 1u)
      << r.err;
  EXPECT_EQ(r.lines("error"), 1u) << r.err;
  EXPECT_TRUE(noOutputs(root + "/out"));
}

// Out-of-range values (a negative grid size, p_min > 1, a negative voxel size) and an unknown
// key in one of our sections, in the INI file or from --set: one line naming the file, the
// section and the key; exit 1; no outputs.
TEST(RgbdMappingBadInput, OutOfRangeValuesAndUnknownKeysAreNamedWithoutOutputs) {
  const auto root = gmc::testdata::scratchDir("bad_values");
  const auto dir = writeTumFolder(root + "/seq", renderFrames(smallScene(3)));
  const std::string ini = root + "/bad.ini";
  struct Case {
    std::string text, override_, expected;
  };
  const std::vector<Case> cases = {
      {"[GMC]\ngrid_cols = -3\n", "", "[GMC] grid_cols: "},
      {"[GMC]\np_min = 1.5\n", "", "[GMC] p_min: "},
      {"[Mapping]\nresolution = -0.05\n", "", "[Mapping] resolution: "},
      {"[Odometry]\nmin_static_inlier = 20\n", "", "[Odometry] min_static_inlier: unknown key"},
      {"", "GMS.grid_rows=-1", "[GMS] grid_rows: "},
      {"", "Frontend.max_featurs=500", "[Frontend] max_featurs: unknown key"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text + c.override_);
    std::ofstream(ini, std::ios::trunc) << c.text;
    const std::string out = root + "/out";
    std::vector<std::string> extra;
    if (!c.override_.empty()) extra = {"--set", c.override_};
    const AppRun r = runMappingWith(ini, dir, out, extra);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(r.lines("gmc-rgbd-mapping: error: " + ini + ": " + c.expected), 1u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(noOutputs(out));
  }
}

// Saturated frames: an all-white RGB image whose depth is 65535 everywhere (the largest value
// a 16-bit depth PNG holds, 13.1 m, beyond every depth limit), an all-white image with good
// depth, and good RGB with saturated depth. No crash: each is marked lost (named on stderr,
// counted), never inserted into the map, and tracking resumes on the next frame.
TEST(RgbdMappingBadInput, SaturatedFramesAreLostCountedAndKeptOutOfTheMap) {
  const auto root = gmc::testdata::scratchDir("bad_saturated");
  const auto options = smallScene(20);
  auto frames = renderFrames(options);
  frames[5].rgb.setTo(cv::Scalar::all(255));
  frames[5].depth.setTo(65535);
  frames[9].rgb.setTo(cv::Scalar::all(255));
  frames[13].depth.setTo(65535);
  const auto dir = writeTumFolder(root + "/seq", frames);
  const AppRun r = runMapping(dir, root + "/out");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.count("frames"), 20);
  EXPECT_EQ(r.lostFrames(), (std::vector<int>{5, 9, 13})) << r.err;
  EXPECT_EQ(r.count("lost"), 3) << r.err;
  EXPECT_EQ(r.count("tracked"), 17) << r.err;
  EXPECT_EQ(r.count("map_inserts"), 17) << r.summary;
  // Predicted over each lost frame, then tracked again: the trajectory stays on the truth
  // (measured: 2.6 cm at worst, on a lost frame; 1.8 cm without the bad frames, as most
  // features lie on the far wall where depth comes in steps of about 4 cm). A saturated
  // frame taken at its word, 13 m deep, would be off by far more.
  const auto ate = gmc::datasets::computeAte(groundTruth(options, 0, 20),
                                             gmc::datasets::readTumTrajectory(root + "/out/trajectory_tum.txt"));
  EXPECT_EQ(ate.pairs, 20u);
  EXPECT_LT(ate.error.max, 0.04);
  // Nothing of the saturated depth reaches the map: every occupied voxel is inside the room.
  octomap::OcTree tree(root + "/out/map.bt");
  size_t occupied = 0, far = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    ++occupied;
    far += it.getCoordinate().norm() > 8.0f;
  }
  EXPECT_GT(occupied, 100u);
  EXPECT_EQ(far, 0u);
}

/// One walker passing 0.5 m in front of a narrow-angle camera (320x240, fx = fy = 600, 30 x 23
/// degrees) at chest height, so for a few frames the person is all the camera sees.
gmc::sim::SimOptions personFillsViewScene() {
  auto o = smallScene(100000, 1.2);
  o.simulator.threads = 1;
  o.camera.fx = o.camera.fy = 600, o.camera.cx = 160, o.camera.cy = 120;
  o.people.walkers = 1;
  o.people.distance_min = o.people.distance_max = 0.5;
  o.people.path_slant = 0;
  o.people.speed_min = o.people.speed_max = 0.8;
  return o;
}

/// The first frame in which the person covers every pixel, searched over one walking cycle
/// (back and forth) at 1/8 of the resolution: the room and the walker do not depend on it.
int firstFrameFilledByThePerson(gmc::sim::SimOptions o) {
  o.camera.fx /= 8, o.camera.fy /= 8, o.camera.cx /= 8, o.camera.cy /= 8;
  o.camera.width /= 8, o.camera.height /= 8;
  const gmc::sim::Simulator sim(o);
  const int cycle = static_cast<int>(2 * 6.4 / o.people.speed_max * o.simulator.fps) + 1;
  for (int i = 0; i < cycle; ++i)
    if (cv::countNonZero(sim.renderFrame(i).mask) == o.camera.width * o.camera.height) return i;
  return -1;
}

/// Error (m) of the estimated camera motion from frame a to frame b against the truth.
double motionError(const std::vector<gmc::datasets::StampedPose>& est,
                   const std::vector<gmc::datasets::StampedPose>& truth, size_t a, size_t b) {
  const Eigen::Vector3d e = (est[a].pose.inverse() * est[b].pose).translation();
  const Eigen::Vector3d t = (truth[a].pose.inverse() * truth[b].pose).translation();
  return (e - t).norm();
}

// The whole view is one walking person for a few frames (the simulator's walker right in
// front of the camera): no crash; each frame is tracked or lost and counted; frames are lost
// only while the person is in view; once it has left, tracking is back and the camera motion
// is right again. The untextured walker gives no matches; the frame where it covers all but
// a strip of wall at the edge: that frame must be lost, not tracked 17 cm off and then
// extrapolated (which left the camera 0.51 m off before the position-sigma check).
TEST(RgbdMappingBadInput, PersonFillingTheWholeViewIsSurvivedAndTrackingRecovers) {
  const auto root = gmc::testdata::scratchDir("bad_person");
  const auto options = personFillsViewScene();
  const int full = firstFrameFilledByThePerson(options);
  ASSERT_GE(full, 30) << "the walker never fills the view (or does so too early)";
  const int first = full - 30, count = 75;
  const gmc::sim::Simulator sim(options);
  std::vector<RgbdFrame> frames;
  std::vector<int> person_px;
  for (int i = first; i < first + count; ++i) {
    const auto f = sim.renderFrame(i);
    frames.push_back(f.frame);
    person_px.push_back(cv::countNonZero(f.mask));
  }
  const int all_px = options.camera.width * options.camera.height;
  const auto filled = std::count(person_px.begin(), person_px.end(), all_px);
  ASSERT_GE(filled, 3) << "the person fills the view in too few frames";
  const int enters = static_cast<int>(std::find_if(person_px.begin(), person_px.end(), [](int n) { return n > 0; }) -
                                      person_px.begin());
  const int left = count - static_cast<int>(std::find_if(person_px.rbegin(), person_px.rend(),
                                                          [](int n) { return n > 0; }) - person_px.rbegin());
  ASSERT_GE(enters, 10) << "the person must enter a view tracked for a while";
  ASSERT_LE(left, count - 20) << "the sequence must go on after the person has left";

  const auto dir = writeTumFolder(root + "/seq", frames);
  const AppRun r = runMapping(dir, root + "/out", {"--set", "Dataset.fx=600", "--set", "Dataset.fy=600",
                                                   "--set", "Dataset.cx=160", "--set", "Dataset.cy=120"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.count("frames"), count);
  EXPECT_EQ(r.count("tracked") + r.count("lost"), count) << r.summary;
  // Lost only while the person is in view (or just after: the re-anchored keyframe needs
  // a frame to be matched against).
  for (int lost : r.lostFrames()) {
    EXPECT_GE(lost, enters) << r.err;
    EXPECT_LT(lost, left + 3) << "not recovered after the person left\n" << r.err;
  }
  const auto trajectory = gmc::datasets::readTumTrajectory(root + "/out/trajectory_tum.txt");
  const auto truth = groundTruth(options, first, count);
  ASSERT_EQ(trajectory.size(), truth.size());
  // Recovered: over the last 15 frames the camera motion is right to about the noise of
  // this scene (features on the far wall; without the person up to 4 cm over 15 frames).
  const double after = motionError(trajectory, truth, count - 16, count - 1);
  const double passage = motionError(trajectory, truth, static_cast<size_t>(enters - 1), count - 16);
  std::printf("  person fills the view in %ld frames (in view %d-%d), %ld lost; motion error %.3f m "
              "over the passage, %.3f m over the 15 frames after\n",
              static_cast<long>(filled), enters, left - 1, r.count("lost"), passage, after);
  // With the landmark map the strip frame no longer reaches the position-sigma check:
  // its few static landmarks are outvoted and it is lost for too few inliers (the check
  // stays, see doc/robustness.md). The passage error went 0.51 m -> 0.09 m (sigma
  // check) -> 0.002 m (landmark map).
  EXPECT_LT(after, 0.08);
  EXPECT_LT(passage, 0.05);
}

// Ctrl-C and SIGTERM on the real executable (a child process): it stops reading, tracks the
// frames already read, exits 0 and writes the trajectory, map and summary of the frames
// processed so far, complete (no temporary file left) and loadable. One overlay per frame
// shows progress. Realtime (Ctrl-C): the map queue is drained or its skips counted.
TEST(RgbdMappingBadInput, SigtermAndSigintStopReadingAndWriteCompleteOutputs) {
#ifndef GMC_RGBD_MAPPING_EXE
  GTEST_SKIP() << "gmc-rgbd-mapping is not part of this build";
#else
  const auto root = gmc::testdata::scratchDir("bad_signal");
  const auto dir = writeTumFolder(root + "/seq", renderFrames(smallScene(20)));
  for (const auto& [sig, realtime] : {std::pair{SIGTERM, false}, std::pair{SIGINT, false}, std::pair{SIGINT, true}}) {
    SCOPED_TRACE(std::string(sig == SIGTERM ? "SIGTERM" : "SIGINT") + (realtime ? " realtime" : ""));
    const std::string out = root + "/out_" + std::to_string(sig) + (realtime ? "_realtime" : "");
    fs::create_directories(out);
    auto overlays = [&] {
      size_t n = 0;
      std::error_code ec;
      for (fs::directory_iterator it(out + "/overlays", ec), end; !ec && it != end; it.increment(ec))
        n += it->path().filename().string()[0] != '.';  // temporaries start with a dot
      return n;
    };
    gmc::testdata::ChildProcess child(
        GMC_RGBD_MAPPING_EXE,
        {GMC_SOURCE_DIR "/config/default.ini", dir, "--out", out, "--set", "Dataset.camera=custom", "--set",
         "Dataset.fx=267.7", "--set", "Dataset.fy=269.6", "--set", "Dataset.cx=160", "--set", "Dataset.cy=123.8",
         "--set", "Dataset.repeat=100000", "--set", "Output.overlay_every=1", "--set",
         std::string("Playback.mode=") + (realtime ? "realtime" : "as_fast_as_possible")},
        out + ".log");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    while (overlays() < 5 && !child.wait() && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_TRUE(child.running()) << "ended before the signal:\n" << child.output();
    ASSERT_GE(overlays(), 5u) << "no progress within 5 minutes:\n" << child.output();
    child.signal(sig);
    const auto status = child.wait(std::chrono::minutes(5));
    ASSERT_TRUE(status.has_value()) << "still running 5 minutes after the signal";
    ASSERT_TRUE(WIFEXITED(*status)) << "ended by signal " << WTERMSIG(*status) << ":\n" << child.output();
    EXPECT_EQ(WEXITSTATUS(*status), 0) << child.output();
    EXPECT_NE(child.output().find("(interrupted)"), std::string::npos) << child.output();

    const std::string summary = readFile(out + "/summary.json");
    EXPECT_NE(summary.find("\"interrupted\": true"), std::string::npos) << summary;
    AppRun parsed;
    parsed.summary = summary;
    const long frames = parsed.count("frames");
    EXPECT_GE(frames, 5);
    EXPECT_LT(frames, 200) << "the signal did not stop the run soon";
    // Every processed frame is in the trajectory (and drew its overlay), nothing more.
    std::ifstream trajectory(out + "/trajectory_tum.txt");
    long lines = 0;
    for (std::string line; std::getline(trajectory, line);) lines += !line.empty() && line[0] != '#';
    EXPECT_EQ(lines, frames);
    EXPECT_EQ(gmc::datasets::readTumTrajectory(out + "/trajectory_tum.txt").size(), static_cast<size_t>(frames));
    EXPECT_EQ(overlays(), static_cast<size_t>(frames));
    // The map loads and holds what the tracked frames saw.
    octomap::OcTree tree(0.1);
    ASSERT_TRUE(tree.readBinary(out + "/map.bt")) << "map.bt does not load";
    EXPECT_GT(tree.size(), 1000u);
    EXPECT_EQ(parsed.count("map_inserts") + parsed.count("map_skipped"), parsed.count("tracked"));
    if (!realtime) {
      EXPECT_EQ(parsed.count("map_skipped"), 0);
    }
    for (const auto& e : fs::directory_iterator(out))
      EXPECT_NE(e.path().filename().string()[0], '.') << "temporary file left: " << e.path();
  }
#endif
}

}  // namespace

/// Distance of trajectory pose k from the straight path between poses a and b (by stamp).
double offPath(const std::vector<gmc::datasets::StampedPose>& t, size_t a, size_t k, size_t b) {
  const double f = (t[k].stamp - t[a].stamp) / (t[b].stamp - t[a].stamp);
  const Eigen::Vector3d on = t[a].pose.translation() + f * (t[b].pose.translation() - t[a].pose.translation());
  return (t[k].pose.translation() - on).norm();
}

// Four black frames in the middle of a moving camera's sequence are lost (their live
// poses are predictions, the velocity halved each frame, so they fall behind the
// camera); once frame 10 is tracked again, trajectory_tum.txt holds them on the path
// between frames 5 and 10. tracking.csv keeps the live poses.
TEST(RgbdMappingBadInput, LostFramesAreBridgedInTheTrajectoryOnceTrackingResumes) {
  const auto root = gmc::testdata::scratchDir("bad_bridge");
  auto frames = renderFrames(smallScene(16));
  for (int i = 6; i < 10; ++i) frames[static_cast<size_t>(i)].rgb.setTo(cv::Scalar::all(0));
  const auto dir = writeTumFolder(root + "/seq", frames);
  const AppRun bridged = runMapping(dir, root + "/out", {"--set", "Output.map=false"});
  const AppRun live = runMapping(dir, root + "/out_live", {"--set", "Output.map=false", "--set", "Odometry.revise_lost=false"});
  ASSERT_EQ(bridged.exit_code, 0) << bridged.err;
  ASSERT_EQ(live.exit_code, 0) << live.err;
  EXPECT_EQ(bridged.count("lost"), 4) << bridged.err;
  const auto b = gmc::datasets::readTumTrajectory(root + "/out/trajectory_tum.txt");
  const auto l = gmc::datasets::readTumTrajectory(root + "/out_live/trajectory_tum.txt");
  ASSERT_EQ(b.size(), 16u);
  ASSERT_EQ(l.size(), 16u);
  double bridged_off = 0, live_off = 0;
  for (size_t k = 6; k < 10; ++k) {
    bridged_off = std::max(bridged_off, offPath(b, 5, k, 10));
    live_off = std::max(live_off, offPath(l, 5, k, 10));
  }
  std::printf("  4 lost frames: %.5f m off the path between the tracked ones bridged, %.5f m live\n", bridged_off,
              live_off);
  EXPECT_LT(bridged_off, 1e-6);
  EXPECT_GT(live_off, 1e-3);
  for (size_t k : {0u, 5u, 10u, 15u})  // tracked frames are the same either way
    EXPECT_LT((b[k].pose.translation() - l[k].pose.translation()).norm(), 1e-9) << k;
}
