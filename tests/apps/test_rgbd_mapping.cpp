#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <octomap/OcTree.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/TPixelLabelInfo.h>
#include <mrpt/serialization/CArchive.h>

#include "gmc/apps/mapping_observers.h"
#include "gmc/apps/rawlog_filter_app.h"
#include "gmc/apps/rgbd_mapping_app.h"
#include "gmc/datasets/evaluation.h"
#include "run_app.h"
#include "test_data.h"
#include "wall_sequence.h"

namespace {

namespace fs = std::filesystem;

int runMapping(std::vector<std::string> args) {
  return gmc::testdata::runApp<gmc::apps::RgbdMappingApp>("gmc-rgbd-mapping", std::move(args));
}

/// The rows of a CSV the app wrote, split at commas; its first line goes to `header`.
std::vector<std::vector<std::string>> readCsv(const std::string& path, std::string& header) {
  std::ifstream csv(path);
  std::getline(csv, header);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(csv, line);) {
    std::vector<std::string> fields;
    std::stringstream ss(line);
    for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
    rows.push_back(fields);
  }
  return rows;
}

TEST(RgbdMappingApp, WallSequenceEndToEnd) {
  const auto root = gmc::testdata::scratchDir("mapping_wall");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 40);
  const auto out = root + "/out";
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", out, "--set",
                        "Dataset.anchor_to_groundtruth=true", "--set", "Output.overlay_every=20"}),
            0);
  const auto est = gmc::datasets::readTumTrajectory(out + "/trajectory_tum.txt");
  const auto gt = gmc::datasets::readTumTrajectory(seq + "/groundtruth.txt");
  ASSERT_EQ(est.size(), 40u);
  const auto ate = gmc::datasets::computeAte(gt, est);
  std::printf("  wall sequence: ATE %.4f m over %zu frames\n", ate.error.rmse, ate.pairs);
  EXPECT_LT(ate.error.rmse, 0.005);
  // Anchored at ground truth, so the end position itself is right (no alignment needed).
  EXPECT_NEAR(est.back().pose.translation().x(), 0.39, 0.01);

  octomap::OcTree tree(out + "/map.bt");
  size_t occupied = 0;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) occupied += tree.isNodeOccupied(*it);
  EXPECT_GT(occupied, 100u);
  EXPECT_TRUE(fs::exists(out + "/summary.json"));
  EXPECT_EQ(std::distance(fs::directory_iterator(out + "/overlays"), fs::directory_iterator{}), 2);
}

TEST(RgbdMappingApp, RepeatPlaysTheInputAgainWithLaterStampsAndLogsMemory) {
  const auto root = gmc::testdata::scratchDir("mapping_repeat");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 12);
  const auto out = root + "/out";
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", out, "--set", "Dataset.repeat=3",
                        "--set", "Output.memory_every=4", "--set", "Output.map=false"}),
            0);
  const auto est = gmc::datasets::readTumTrajectory(out + "/trajectory_tum.txt");
  ASSERT_EQ(est.size(), 36u);
  for (size_t i = 1; i < est.size(); ++i) EXPECT_NEAR(est[i].stamp - est[i - 1].stamp, 1.0 / 30.0, 1e-4) << i;
  // The camera jumps back 11 cm at each new pass; tracking follows it.
  EXPECT_NEAR(est[11].pose.translation().x() - est[12].pose.translation().x(), 0.11, 0.01);
  std::ifstream csv(out + "/memory.csv");
  std::string line;
  int rows = -1;  // header
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 9);
  EXPECT_TRUE(fs::exists(out + "/memory.png"));
  std::ifstream summary(out + "/summary.json");
  const std::string json((std::istreambuf_iterator<char>(summary)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"peak_rss_mb\": "), std::string::npos);
  EXPECT_EQ(json.find("\"peak_rss_mb\": 0,"), std::string::npos);
}

TEST(GroundTruthScores, PosePointsOnPeopleCountOnlyTheRefinementsObservationsOfTrackedFrames) {
  cv::Mat mask(480, 640, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(100, 100, 50, 200)).setTo(255);  // a person
  gmc::vo::FrameTracking t;
  t.state = gmc::vo::TrackingState::Tracking;
  t.keypoints = {{120, 150}, {400, 300}, {130, 250}, {500, 50}};
  t.keypoint_in_pose = {1, 1, 0, 1};  // the third is on the person but held no pose
  const auto n = gmc::apps::countPosePoints(t, mask);
  EXPECT_EQ(n.points, 3u);
  EXPECT_EQ(n.on_people, 1u);
  EXPECT_NEAR(n.share(), 1.0 / 3.0, 1e-12);
  t.state = gmc::vo::TrackingState::Lost;  // a predicted pose rests on nothing
  EXPECT_EQ(gmc::apps::countPosePoints(t, mask).points, 0u);
}

TEST(RgbdMappingApp, TrackingLogHasEveryFramesStatePoseAndLostReason) {
  const auto root = gmc::testdata::scratchDir("mapping_tracking_log");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 10);
  // Frame 6 loses its depth: nothing to refine on, so it is lost and says why.
  std::ifstream list(seq + "/depth.txt");
  std::string line, depth_file;
  for (int i = 0; i < 6 && std::getline(list, line);) depth_file = line.substr(line.find(' ') + 1), ++i;
  cv::imwrite(seq + "/" + depth_file, cv::Mat(480, 640, CV_16UC1, cv::Scalar(0)));
  const auto out = root + "/out";
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", out, "--set", "Output.tracking_log=true",
                        "--set", "Output.map=false"}),
            0);
  const auto est = gmc::datasets::readTumTrajectory(out + "/trajectory_tum.txt");
  const auto rows = readCsv(out + "/tracking.csv", line);
  EXPECT_EQ(line.rfind("frame,stamp,state,keyframe,window_shift,window_discarded,rejoined,start_consensus,", 0), 0u) << line;
  ASSERT_EQ(rows.size(), 10u);
  ASSERT_EQ(est.size(), 10u);
  const Eigen::Vector3d midway = 0.5 * (est[4].pose.translation() + est[6].pose.translation());
  EXPECT_LT((est[5].pose.translation() - midway).norm(), 1e-6) << "the lost frame is not bridged";
  for (size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 30u) << i;
    EXPECT_EQ(rows[i][0], std::to_string(i + 1));
    EXPECT_NEAR(std::stod(rows[i][1]), est[i].stamp, 1e-6);
    // The log keeps the live pose; the trajectory holds the lost frame bridged between
    // its tracked neighbours (doc/odometry.md, step 5), which the next check covers.
    if (i != 5) {
      EXPECT_NEAR(std::stod(rows[i][22]), est[i].pose.translation().x(), 1e-5) << i;
    }
    const std::string expected = i == 0 ? "initialized" : i == 5 ? "lost" : "tracking";
    EXPECT_EQ(rows[i][2], expected) << i;
    EXPECT_EQ(rows[i][29] != "\"\"", i == 5) << i << ": " << rows[i][29];
    EXPECT_EQ(rows[i][6], "0") << i;  // no re-anchor, nothing to rejoin
    EXPECT_EQ(rows[i][7], "0") << i;  // a static wall: the start consensus agrees with the poses
    if (expected == "tracking") {  // the refinement's median errors on a clean rendered wall
      EXPECT_LT(std::stod(rows[i][20]), 2.0) << i;
      EXPECT_LT(std::stod(rows[i][21]), 0.02) << i;
    }
    // Landmarks to re-find exist only after a tracked frame (none after the first frame,
    // which is initialised, and after the lost 6th).
    const int to_refind = std::stoi(rows[i][15]), refound = std::stoi(rows[i][16]);
    EXPECT_LE(refound, to_refind) << i;
    EXPECT_EQ(to_refind > 0, i >= 2 && i != 6) << i << ": " << to_refind;
  }
}

// The trajectory's smoothing gives a pose smoothing_frames frames later; at the input's
// end the app finishes the filter chain and writes the last frames' fits too (they
// differ from the live poses tracking.csv keeps), not their live poses.
TEST(RgbdMappingApp, TheLastFramesOfTheTrajectoryAreSmoothedAtTheInputsEnd) {
  const auto root = gmc::testdata::scratchDir("mapping_last_frames");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 20);
  // Largest |trajectory - live| in x over the last k frames, and over the frames before.
  const auto lastAndEarlierShift = [&](const std::string& out, int k) {
    const auto est = gmc::datasets::readTumTrajectory(out + "/trajectory_tum.txt");
    std::string header;
    const auto rows = readCsv(out + "/tracking.csv", header);
    EXPECT_EQ(est.size(), rows.size());
    std::pair<double, double> shift{0, 0};
    for (size_t i = 1; i < std::min(est.size(), rows.size()); ++i) {
      const double d = std::abs(std::stod(rows[i][22]) - est[i].pose.translation().x());
      double& worst = i + static_cast<size_t>(k) >= rows.size() ? shift.first : shift.second;
      worst = std::max(worst, d);
    }
    return shift;
  };
  const auto out = root + "/out";
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", out, "--set", "Output.tracking_log=true",
                        "--set", "Output.map=false"}),
            0);
  const auto [last, earlier] = lastAndEarlierShift(out, 6);
  std::printf("  smoothed: the last 6 frames moved by up to %.2e m, the earlier ones by up to %.2e m\n", last, earlier);
  EXPECT_GT(last, 2e-6) << "the last frames kept their live pose";
  EXPECT_GT(earlier, 2e-6);
  EXPECT_LT(last, 0.01);
  const auto live = root + "/live";
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", live, "--set", "Output.tracking_log=true",
                        "--set", "Output.map=false", "--set", "Odometry.smoothing_frames=0"}),
            0);
  const auto [last_live, earlier_live] = lastAndEarlierShift(live, 6);
  EXPECT_LT(std::max(last_live, earlier_live), 2e-6) << "without smoothing the trajectory is the live poses";
}

// map_matches.csv: one row per map match, with the observation that placed its
// landmark (earlier than the frame), and as many refinement inliers per frame as
// tracking.csv counts (scripts/match_truth.py reads it).
TEST(RgbdMappingApp, MatchLogHasEveryMapMatchWithItsLandmarksOrigin) {
  const auto root = gmc::testdata::scratchDir("mapping_match_log");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 8);
  const auto out = root + "/out";
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", out, "--set", "Output.tracking_log=true",
                        "--set", "Output.match_log=true", "--set", "Output.map=false"}),
            0);
  std::string header;
  const auto tracking = readCsv(out + "/tracking.csv", header);
  const auto matches = readCsv(out + "/map_matches.csv", header);
  EXPECT_EQ(header,
            "frame,stamp,state,u,v,x,y,z,origin_x,origin_y,origin_z,origin_stamp,label,established,in_pose,pose_inlier");
  ASSERT_EQ(tracking.size(), 8u);
  std::map<int, int> inliers, rows_per_frame;
  for (const auto& m : matches) {
    ASSERT_EQ(m.size(), 16u);
    const int frame = std::stoi(m[0]);
    ASSERT_GE(frame, 2);  // the first frame only seeds the map
    ASSERT_LE(frame, 8);
    EXPECT_EQ(m[2], tracking[static_cast<size_t>(frame - 1)][2]);
    EXPECT_LT(std::stod(m[11]), std::stod(m[1]));
    EXPECT_GT(std::stod(m[10]), 0.0) << "the origin is a point in front of its camera";
    EXPECT_TRUE(m[15] == "0" || m[14] == "1") << "an inlier that did not go into the pose";
    inliers[frame] += m[15] == "1";
    ++rows_per_frame[frame];
  }
  for (int frame = 2; frame <= 8; ++frame) {
    EXPECT_GT(rows_per_frame[frame], 50) << frame;
    EXPECT_EQ(inliers[frame], std::stoi(tracking[static_cast<size_t>(frame - 1)][12])) << frame;
  }
}

TEST(RgbdMappingApp, TeddyStaysAccurateWithGmc) {
  GMC_REQUIRE_DATA(dir, "tum_fr3_teddy_1_100");
  const auto out = gmc::testdata::scratchDir("mapping_teddy");
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/tum_fr3.ini", dir, "--out", out, "--set",
                        "Output.map=false"}),
            0);
  const auto ate = gmc::datasets::computeAte(gmc::datasets::readTumTrajectory(dir + "/groundtruth.txt"),
                                             gmc::datasets::readTumTrajectory(out + "/trajectory_tum.txt"));
  std::printf("  teddy (100 frames): ATE %.4f m\n", ate.error.rmse);
  EXPECT_GE(ate.pairs, 95u);  // 96 of the 100 RGB stamps have ground truth within 0.02 s
  EXPECT_LT(ate.error.rmse, 0.01);
}

TEST(RgbdMappingApp, ConfigurationErrorsFailWithoutOutputs) {
  const auto root = gmc::testdata::scratchDir("mapping_bad");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 3);
  auto ini = [&](const std::string& name, const std::string& text) {
    std::ofstream(root + "/" + name) << text;
    return root + "/" + name;
  };
  EXPECT_EQ(runMapping({ini("a.ini", "[GMC]\ngrid_colz = 3\n"), seq, "--out", root + "/o1"}), 1);
  EXPECT_EQ(runMapping({ini("b.ini", "[GMC]\np_min = 1.5\n"), seq, "--out", root + "/o2"}), 1);
  EXPECT_EQ(runMapping({ini("c.ini", "[Nonsense]\nx = 1\n"), seq, "--out", root + "/o3"}), 1);
  EXPECT_EQ(runMapping({ini("d.ini", "[Filters]\nchain = gmc, blur\n"), seq, "--out", root + "/o4"}), 1);
  EXPECT_EQ(runMapping({ini("e.ini", ""), root + "/missing", "--out", root + "/o5"}), 1);
  EXPECT_EQ(runMapping({root + "/missing.ini", seq, "--out", root + "/o6"}), 1);
  EXPECT_EQ(runMapping({ini("f.ini", ""), seq}), 2);  // no --out
  for (int i = 1; i <= 6; ++i) EXPECT_FALSE(fs::exists(root + "/o" + std::to_string(i) + "/trajectory_tum.txt"));
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Unpaced, the map runs on its own thread but takes every tracked frame in order: two
// runs give the same bytes.
TEST(RgbdMappingApp, UnpacedRunsAreByteIdentical) {
  const auto root = gmc::testdata::scratchDir("mapping_deterministic");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 20);
  for (const char* out : {"/a", "/b"})
    ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", root + out, "--set",
                          "Playback.map_queue=1", "--set", "Playback.frame_queue=1"}),
              0);
  EXPECT_EQ(readBytes(root + "/a/trajectory_tum.txt"), readBytes(root + "/b/trajectory_tum.txt"));
  const std::string map = readBytes(root + "/a/map.bt");
  EXPECT_GT(map.size(), 1000u);
  EXPECT_EQ(map, readBytes(root + "/b/map.bt"));
  const auto summary = nlohmann::json::parse(readBytes(root + "/a/summary.json"));
  EXPECT_EQ(summary.at("map_inserts"), summary.at("tracked"));
  EXPECT_EQ(summary.at("map_skipped"), 0);
  EXPECT_EQ(summary.at("dropped"), 0);
  EXPECT_EQ(summary.at("stages").at("map").at("items"), summary.at("tracked"));
  EXPECT_EQ(summary.at("queues").at("map").at("capacity"), 1);
}

// Realtime with a map far slower than the camera (every pixel, 2 cm voxels): the
// odometry keeps the camera's pace and the map skips frames, each one counted.
TEST(RgbdMappingApp, RealtimeSlowMapSkipsCountedFramesAndOdometryKeepsUp) {
  const auto root = gmc::testdata::scratchDir("mapping_realtime");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 30);
  ASSERT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", root + "/out", "--set",
                        "Playback.mode=realtime", "--set", "Playback.rate=0.5", "--set", "Playback.map_queue=2",
                        "--set", "Mapping.pixel_step=1", "--set", "Mapping.resolution=0.02"}),
            0);
  const auto summary = nlohmann::json::parse(readBytes(root + "/out/summary.json"));
  const long tracked = summary.at("tracked"), inserted = summary.at("map_inserts"),
             skipped = summary.at("map_skipped");
  EXPECT_EQ(summary.at("frames").get<long>() + summary.at("dropped").get<long>(), 30);
  EXPECT_EQ(inserted + skipped, tracked);
  EXPECT_GT(skipped, 0) << "the map kept up: the test does not load it enough";
  EXPECT_GT(inserted, 0);
  EXPECT_EQ(summary.at("map").at("frames_inserted"), inserted);
  EXPECT_TRUE(summary.contains("realtime_lag_s"));
  EXPECT_LE(summary.at("queues").at("map").at("high_water").get<long>(), 2);
}

void testHandler(int) {}

// A run that fails mid-way (no ground-truth pose for the first frame) puts the caller's
// signal handlers back (they were left pointing at the app's before).
TEST(RgbdMappingApp, SignalHandlersAreRestoredWhenRunThrows) {
  const auto root = gmc::testdata::scratchDir("mapping_signals");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 3);
  std::ofstream(root + "/late_gt.txt") << "5000.0 0 0 0 0 0 0 1\n5000.1 0 0 0 0 0 0 1\n";
  const auto old_int = std::signal(SIGINT, testHandler);
  const auto old_term = std::signal(SIGTERM, testHandler);
  EXPECT_EQ(runMapping({GMC_SOURCE_DIR "/config/default.ini", seq, "--out", root + "/out", "--set",
                        "Dataset.groundtruth=" + root + "/late_gt.txt", "--set", "Dataset.anchor_to_groundtruth=true"}),
            1);
  EXPECT_EQ(std::signal(SIGINT, old_int), &testHandler);
  EXPECT_EQ(std::signal(SIGTERM, old_term), &testHandler);
}

TEST(RawlogFilterApp, WritesLabelledObservationsMrptReads) {
  const auto root = gmc::testdata::scratchDir("rawlog_filter");
  const auto seq = gmc::testdata::makeWallSequence(root + "/seq", 6);
  std::ofstream(root + "/f.ini") << "[Filters]\nchain = decimate, gmc\n[Decimate]\nkeep_every = 2\n";
  ASSERT_EQ(gmc::testdata::runApp<gmc::apps::RawlogFilterApp>("gmc-rawlog-filter",
                                                             {root + "/f.ini", seq, root + "/out.rawlog"}),
            0);
  mrpt::io::CFileGZInputStream in(root + "/out.rawlog");
  auto archive = mrpt::serialization::archiveFrom(in);
  size_t n = 0, entry = 0;
  mrpt::obs::CActionCollection::Ptr acts;
  mrpt::obs::CSensoryFrame::Ptr sf;
  mrpt::obs::CObservation::Ptr obs;
  while (mrpt::obs::CRawlog::getActionObservationPairOrObservation(archive, acts, sf, obs, entry)) {
    auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(obs);
    ASSERT_TRUE(scan);
    ASSERT_TRUE(scan->hasPixelLabels());
    EXPECT_EQ(scan->pixelLabels->getLabelName(0), "dynamic");
    ++n;
  }
  EXPECT_EQ(n, 3u);  // every second of 6 frames
  EXPECT_EQ(gmc::testdata::runApp<gmc::apps::RawlogFilterApp>("gmc-rawlog-filter", {root + "/f.ini", seq}), 2);
}

}  // namespace
