#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "gmc/config/ini.h"
#include "gmc/datasets/evaluation.h"
#include "gmc/sim/sim_config.h"
#include "gmc/sim/simulator.h"
#include "gmc/vo/dynamic_mask.h"
#include "gmc/vo/odometry.h"

namespace {

/// Renders simulated frame i and tracks it (blanked: an all-black image, as a covered lens).
struct SimStep {
  gmc::sim::SimFrame rendered;
  gmc::vo::FrameTracking tracking;
};
SimStep trackSimFrame(const gmc::sim::Simulator& sim, gmc::vo::RgbdOdometry& vo, int i, bool blanked = false) {
  SimStep step{sim.renderFrame(i), {}};
  const auto& f = step.rendered.frame;
  cv::Mat gray;
  cv::cvtColor(f.rgb, gray, cv::COLOR_BGR2GRAY);
  if (blanked) gray.setTo(0);
  step.tracking = vo.process(gray, f.depth, f.depth_units, f.camera, f.stamp);
  return step;
}

/// The exact simulator without people, the camera moving on a half sphere.
gmc::sim::SimOptions emptyHalfsphere() {
  auto o = gmc::sim::SimOptions::exact();
  o.people.walkers = 0;
  o.trajectory.style = "halfsphere";
  return o;
}

/// Runs the odometry over simulated frames; returns the worst position error against
/// the ground truth (both expressed relative to the first frame).
double worstError(const gmc::sim::SimOptions& options, const gmc::vo::OdometryConfig& config, int frames,
                  int* lost = nullptr, double* rms = nullptr) {
  const gmc::sim::Simulator sim(options);
  gmc::vo::RgbdOdometry vo(config);
  const gmc::Isometry T0_inv = sim.cameraPose(0).inverse();
  double worst = 0, sum_sq = 0;
  for (int i = 0; i < frames; ++i) {
    const auto [f, t] = trackSimFrame(sim, vo, i);
    if (lost) *lost += t.state == gmc::vo::TrackingState::Lost;
    const gmc::Isometry truth = T0_inv * f.T_world_camera;
    const double e = (t.T_world_camera.translation() - truth.translation()).norm();
    worst = std::max(worst, e);
    sum_sq += e * e;
  }
  if (rms) *rms = std::sqrt(sum_sq / frames);
  return worst;
}

// Exact correspondences are recovered exactly (Refinement.RecoversKnownMotionExactly...);
// from rendered images the limit is keypoint localisation on a point-sampled (aliased)
// renderer, a few tenths of a pixel.
TEST(OdometrySim, RecoversTheCameraMotionWithoutNoiseOrPeople) {
  auto o = gmc::sim::SimOptions::exact();
  o.people.walkers = 0;
  o.trajectory.style = "xyz";
  int lost = 0;
  const double err = worstError(o, {}, 40, &lost);
  std::printf("  noise-free, no people, 40 frames: worst position error %.5f m\n", err);
  EXPECT_EQ(lost, 0);
  EXPECT_LT(err, 0.005);
}

// The map matches a frame reports (map_matches.csv) carry the observation that placed
// each landmark: in a static scene nearly each is the same world point as the match, by
// the true poses alone (1.5 % are wrong matches, most beyond 5 m), those that went
// into the pose are the keypoints marked so, and the refinement's inliers among them.
TEST(OdometrySim, MapMatchesNameTheObservationThatPlacedTheirLandmark) {
  const gmc::sim::Simulator sim(emptyHalfsphere());
  gmc::vo::RgbdOdometry vo{gmc::vo::OdometryConfig{}};
  std::map<double, gmc::Isometry> truth;
  int records = 0, far = 0;
  for (int i = 0; i < 30; ++i) {
    const auto [f, t] = trackSimFrame(sim, vo, i);
    truth[f.frame.stamp] = f.T_world_camera;
    int in_pose = 0, pose_inliers = 0;
    for (const auto& m : t.map_matches) {
      ASSERT_TRUE(truth.count(m.landmark_origin_stamp)) << "frame " << i;
      EXPECT_LT(m.landmark_origin_stamp, f.frame.stamp);
      const double d = (truth[m.landmark_origin_stamp] * m.landmark_origin - f.T_world_camera * m.point_cur).norm();
      // scripts/match_truth.py's tolerance: depth read at a rounded pixel moves by
      // centimetres at 5 m on the floor's grazing view, even without sensor noise.
      far += d > 0.03 + 0.01 * m.point_cur.z() * m.point_cur.z();
      ++records;
      in_pose += m.in_pose;
      pose_inliers += m.pose_inlier;
      EXPECT_EQ(m.in_pose, t.keypoint_in_pose[static_cast<size_t>(m.keypoint)] != 0);
      EXPECT_TRUE(m.in_pose || !m.pose_inlier);
    }
    EXPECT_EQ(pose_inliers, t.num_inliers) << "frame " << i;
    int marked = 0;
    for (auto k : t.keypoint_in_pose) marked += k;
    EXPECT_EQ(in_pose, marked) << "frame " << i;
  }
  std::printf("  static scene, 30 frames: %d map matches, %d not the same world point\n", records, far);
  EXPECT_GT(records, 29 * 50);
  EXPECT_LT(far, records / 33) << "more than 3 % of a static scene's matches judged false";
}

// The same image again finds every landmark that held the last pose: the count is of
// landmarks, not of keypoints, and survives keyframes. Moving through the scene finds
// fewer (GFTT's selection changes with the view: doc/odometry.md, "Seventh round").
TEST(OdometrySim, LandmarksThatHeldThePoseAreRefoundInTheSameImage) {
  auto o = gmc::sim::SimOptions::exact();
  o.people.walkers = 0;
  o.trajectory.style = "xyz";
  const gmc::sim::Simulator sim(o);
  const auto f = sim.renderFrame(0).frame;
  cv::Mat gray;
  cv::cvtColor(f.rgb, gray, cv::COLOR_BGR2GRAY);
  const gmc::vo::OdometryConfig config;
  gmc::vo::RgbdOdometry still(config), moving(config);
  for (int i = 0; i < 6; ++i) {
    const auto t = still.process(gray, f.depth, f.depth_units, f.camera, f.stamp + i / 30.0);
    if (i < 2) {
      EXPECT_EQ(t.landmarks_to_refind, 0) << i;  // nothing held a pose before frame 1's
      continue;
    }
    EXPECT_GT(t.landmarks_to_refind, 100) << i;
    EXPECT_EQ(t.landmarks_refound, t.landmarks_to_refind) << i;
  }
  int to_refind = 0, refound = 0;
  for (int i = 0; i < 20; ++i) {
    const auto t = trackSimFrame(sim, moving, i).tracking;
    to_refind += t.landmarks_to_refind;
    refound += t.landmarks_refound;
  }
  std::printf("  moving camera, 20 frames: %d of %d landmarks re-found\n", refound, to_refind);
  EXPECT_GT(to_refind, 0);
  EXPECT_LT(refound, to_refind);
}

TEST(OdometrySim, WalkersDoNotPullTheEstimateWithGmc) {
  auto o = gmc::sim::SimOptions::exact();
  o.people.walkers = 3;
  o.trajectory.style = "static";
  gmc::vo::OdometryConfig with, without;
  without.gmc.enabled = false;
  const double err_with = worstError(o, with, 60), err_without = worstError(o, without, 60);
  std::printf("  static camera, 3 walkers, 60 frames: worst error %.4f m with GMC, %.4f m without\n",
              err_with, err_without);
  EXPECT_LT(err_with, 0.01);
  EXPECT_LT(err_with, err_without);
}

// The crowd scenario (config/sim/crowd.ini: five articulated walkers in a bare office,
// people on a third of the image in the median frame, the nearest within a metre, motion
// blur, depth shadows): the odometry stays within centimetres, where it drifted by
// decimetres without GMC. 150 frames (5 s) keep the test short.
TEST(OdometrySim, CrowdScenarioStaysWithinCentimetres) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/crowd.ini";
  const auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  gmc::vo::OdometryConfig with, without;
  without.gmc.enabled = false;
  double rms_with = 0, rms_without = 0;
  int lost = 0;
  const double worst_with = worstError(options, with, 150, &lost, &rms_with);
  worstError(options, without, 150, nullptr, &rms_without);
  std::printf("  crowd, 150 frames: position error RMS %.4f m (worst %.4f, %d lost) with GMC, RMS %.4f m without\n",
              rms_with, worst_with, lost, rms_without);
  EXPECT_LT(rms_with, 0.03);
  EXPECT_LT(rms_with, 0.5 * rms_without);
}

// Seed 2 of the crowd scenario: at frame 156 the windowed optimisation moved a keyframe
// tracked to 3.2 mm by 25 cm (wrong associations), the next frame jumped back 15 cm and
// the run ended 0.12 m off (ATE). The hand-held camera moves under 1 cm per frame; the
// estimate must not jump by decimetres.
TEST(OdometrySim, CrowdSeed2NeverJumpsByDecimetres) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/crowd.ini";
  auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  options.simulator.seed = 2;
  const gmc::sim::Simulator sim(options);
  gmc::vo::RgbdOdometry vo{gmc::vo::OdometryConfig{}};
  // Between two tracked frames (the first one after lost frames corrects the prediction).
  double largest_step = 0, largest_true_step = 0;
  int discarded = 0;
  bool last_tracked = false;
  gmc::Isometry last = gmc::Isometry::Identity(), last_truth = last;
  for (int i = 0; i < 165; ++i) {
    const auto [f, t] = trackSimFrame(sim, vo, i);
    discarded += t.window_discarded;
    const bool tracked = t.state == gmc::vo::TrackingState::Tracking;
    if (tracked && last_tracked) {
      largest_step = std::max(largest_step, (t.T_world_camera.translation() - last.translation()).norm());
      largest_true_step = std::max(largest_true_step, (f.T_world_camera.translation() - last_truth.translation()).norm());
    }
    last_tracked = tracked;
    last = t.T_world_camera;
    last_truth = f.T_world_camera;
  }
  std::printf("  crowd seed 2, 165 frames: largest step between tracked frames %.3f m (camera %.3f m), %d window "
              "results discarded\n", largest_step, largest_true_step, discarded);
  EXPECT_LT(largest_true_step, 0.015);
  EXPECT_LT(largest_step, 0.1);
}

/// The synchronous scenario (config/sim/synchronous.ini: a group of three walking in step
/// with the camera, 2.8 m ahead) at seed 1, 30 frames: the position errors (against the
/// truth, both relative to the first frame) of the last live pose and the worst of the
/// earlier frames once every revision is applied, and the frames that took the consensus.
struct StartResult {
  double last_error = 0, worst_revised = 0;
  int consensus_frames = 0;
};
StartResult synchronousStart(bool consensus) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/synchronous.ini";
  auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  options.simulator.seed = 1;
  const gmc::sim::Simulator sim(options);
  gmc::vo::OdometryConfig config;
  config.start_consensus.enabled = consensus;
  gmc::vo::RgbdOdometry vo(config);
  const gmc::Isometry T0_inv = sim.cameraPose(0).inverse();
  std::map<long, gmc::Isometry> given;
  std::map<long, gmc::Isometry> truth;
  StartResult r;
  for (int i = 0; i < 30; ++i) {
    const auto [f, t] = trackSimFrame(sim, vo, i);
    given[t.frame_number] = t.T_world_camera;
    truth[t.frame_number] = T0_inv * f.T_world_camera;
    for (const auto& revised : t.revised) given[revised.frame_number] = revised.T_world_camera;
    r.consensus_frames += t.start_consensus;
    r.last_error = (t.T_world_camera.translation() - truth[t.frame_number].translation()).norm();
  }
  for (const auto& [n, T] : given) r.worst_revised = std::max(r.worst_revised, (T.translation() - truth[n].translation()).norm());
  return r;
}

// The group fills the view and moves with the camera: frame to frame it is the best
// explained motion, and the estimate followed it (0.54 m off after 10 frames at seed 1).
// Over the map's first frames the room is the one rigid body that explains them: the
// start consensus takes it and revises the frames given out before.
TEST(OdometrySim, AGroupWalkingWithTheCameraIsNotTakenForTheRoom) {
  const StartResult with = synchronousStart(true), without = synchronousStart(false);
  std::printf("  synchronous seed 1, 30 frames: last error %.4f m, worst revised %.4f m, consensus taken %d times; "
              "without it %.4f / %.4f m\n", with.last_error, with.worst_revised, with.consensus_frames,
              without.last_error, without.worst_revised);
  EXPECT_GE(with.consensus_frames, 1);
  EXPECT_LT(with.last_error, 0.03);
  // The frames before it are put on the path from the first keyframe (2.7 cm at worst;
  // fitted on the few room landmarks each saw they were up to 10 cm off); without the
  // consensus they are 0.87 m off.
  EXPECT_LT(with.worst_revised, 0.05);
  EXPECT_GT(without.last_error, 0.2) << "the scenario must mislead the frame-to-frame choice";
}

/// Renders frames 0..count-1 of the synchronous scenario at `seed` once and tracks each
/// with both odometries: visit(k, rendered frame, tracking) with k = 0 for `first`.
using SynchronousVisit = std::function<void(int, const gmc::sim::SimFrame&, const gmc::vo::FrameTracking&)>;

/// The synchronous scenario's first `count` frames at `seed`, rendered once, through each odometry.
void trackSynchronous(int seed, int count, const std::vector<gmc::vo::RgbdOdometry*>& odometries,
                      const SynchronousVisit& visit) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/synchronous.ini";
  auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  options.simulator.seed = seed;
  const gmc::sim::Simulator sim(options);
  for (int i = 0; i < count; ++i) {
    const auto rendered = sim.renderFrame(i);
    const auto& f = rendered.frame;
    cv::Mat gray;
    cv::cvtColor(f.rgb, gray, cv::COLOR_BGR2GRAY);
    for (size_t k = 0; k < odometries.size(); ++k)
      visit(static_cast<int>(k), rendered, odometries[k]->process(gray, f.depth, f.depth_units, f.camera, f.stamp));
  }
}

void trackSynchronousTwice(int seed, int count, gmc::vo::RgbdOdometry& first, gmc::vo::RgbdOdometry& second,
                           const SynchronousVisit& visit) {
  trackSynchronous(seed, count, {&first, &second}, visit);
}

// Seed 1: a group of three walks in step with the camera (3 cm a frame) from the first
// frame, 1.2-3 m ahead; the room is 3-6 m away. In sampling stream 1 the start consensus
// as it was, or with its samples judged by their mean step alone, leaves the estimate
// standing still with the group (1.19 m ATE over the whole run); in stream 5 settling
// the best samples alone does. With both halves of the fifty-fifth round's change the
// consensus finds the room in the map's first frames in both (doc/odometry.md).
TEST(OdometrySim, AGroupInStepIsNotTakenForTheRoomByTheStartConsensus) {
  const int frames = 40;
  struct Variant {
    const char* name;
    int stream;
    bool mean_step;
    int refit;  // refit_samples; refit_rounds 2 when above 1
    bool follows_room;
  };
  const std::vector<Variant> variants{{"defaults", 1, true, 5, true},  {"mean step only", 1, true, 1, false},
                                      {"as before", 1, false, 1, false}, {"defaults", 5, true, 5, true},
                                      {"settled only", 5, false, 5, false}};
  std::vector<std::unique_ptr<gmc::vo::RgbdOdometry>> odometries;
  std::vector<gmc::vo::RgbdOdometry*> raw;
  for (const auto& v : variants) {
    gmc::vo::OdometryConfig c;
    c.odometry.random_seed = v.stream;
    c.start_consensus.sample_mean_step = v.mean_step;
    c.start_consensus.refit_samples = v.refit;
    c.start_consensus.refit_rounds = v.refit > 1 ? 2 : 1;
    odometries.push_back(std::make_unique<gmc::vo::RgbdOdometry>(c));
    raw.push_back(odometries.back().get());
  }
  std::vector<double> error(variants.size(), 0);
  gmc::Isometry first_truth = gmc::Isometry::Identity();
  trackSynchronous(1, frames, raw, [&](int k, const gmc::sim::SimFrame& rendered, const auto& t) {
    if (t.frame_number == 1) first_truth = rendered.T_world_camera;
    if (t.frame_number != frames) return;
    const gmc::Isometry truth = first_truth.inverse() * rendered.T_world_camera;
    error[static_cast<size_t>(k)] = (t.T_world_camera.translation() - truth.translation()).norm();
  });
  for (size_t k = 0; k < variants.size(); ++k) {
    std::printf("  synchronous seed 1, stream %d, %s: position error at frame %d %.3f m\n", variants[k].stream,
                variants[k].name, frames, error[k]);
    if (variants[k].follows_room) EXPECT_LT(error[k], 0.1) << variants[k].name << ", stream " << variants[k].stream;
    else EXPECT_GT(error[k], 0.5) << variants[k].name << ", stream " << variants[k].stream;
  }
}

/// The synchronous scenario at seed 2 over 60 frames, with the hindsight (first) and
/// without: the worst error of frames 2-20 (every revision applied) relative to frame 30,
/// against the truth's (the world frame may be off by what the first frames missed; their
/// place on the path is what matters). The frames are rendered once for both runs.
std::pair<double, double> synchronousEarlyFrames() {
  gmc::vo::OdometryConfig with_config, without_config;
  without_config.hindsight.enabled = false;
  gmc::vo::RgbdOdometry with(with_config), without(without_config);
  std::map<long, gmc::Isometry> given[2], truth;
  trackSynchronousTwice(2, 60, with, without, [&](int k, const gmc::sim::SimFrame& rendered, const auto& t) {
    given[k][t.frame_number] = t.T_world_camera;
    for (const auto& revised : t.revised) given[k][revised.frame_number] = revised.T_world_camera;
    truth[t.frame_number] = rendered.T_world_camera;
  });
  double worst[2] = {0, 0};
  for (int k = 0; k < 2; ++k)
    for (long n = 2; n <= 20; ++n) {
      const Eigen::Vector3d estimated = given[k][n].translation() - given[k][30].translation();
      const Eigen::Vector3d true_offset = truth[n].translation() - truth[30].translation();
      worst[k] = std::max(worst[k], (estimated - true_offset).norm());
    }
  return {worst[0], worst[1]};
}

// The estimate stands still on a group walking in step with the camera for its first 20
// frames, while the camera walks 3 cm a frame (the start consensus cannot tell: over its
// frames the room and the group explain as many observations), until the room takes over
// at frame 22. A second later the group's landmarks have been seen moving and the map
// holds the room: the first frames are posed again on it, and back from one another.
TEST(OdometrySim, FramesThatFollowedAGroupArePosedAgainOnceTheMapHoldsTheRoom) {
  const auto [with, without] = synchronousEarlyFrames();
  std::printf("  synchronous seed 2, frames 2-20 against frame 30: worst %.3f m with the hindsight, %.3f without\n",
              with, without);
  EXPECT_GT(without, 0.3) << "the scenario must make the first frames follow the group";
  EXPECT_LT(with, 0.1);
}

/// The synchronous scenario at seed 1 with sampling stream 2, 130 frames, with [Window]
/// skip_unheld (first) and without: the ATE of the trajectory as written (every revision
/// applied), and of the live poses of frames 40-130 (once the map holds the room).
struct SkipUnheldResult {
  double written[2] = {0, 0}, live[2] = {0, 0};
};
SkipUnheldResult synchronousWithAndWithoutUnheld() {
  gmc::vo::OdometryConfig with_config, without_config;
  with_config.odometry.random_seed = without_config.odometry.random_seed = 2;
  without_config.window.skip_unheld = false;
  // The start consensus as it was before the fifty-fifth round, which leaves this stream
  // on the group for its first 15 frames (today's finds the room by frame 10).
  for (auto* c : {&with_config, &without_config}) {
    c->start_consensus.refit_samples = c->start_consensus.refit_rounds = 1;
    c->start_consensus.sample_mean_step = false;
  }
  gmc::vo::RgbdOdometry with(with_config), without(without_config);
  std::map<long, gmc::datasets::StampedPose> written[2];
  std::vector<gmc::datasets::StampedPose> live[2], truth[2], live_truth[2];
  trackSynchronousTwice(1, 130, with, without, [&](int k, const gmc::sim::SimFrame& rendered, const auto& t) {
    written[k][t.frame_number] = {t.stamp, t.T_world_camera};
    for (const auto& r : t.revised) written[k][r.frame_number] = {r.stamp, r.T_world_camera};
    truth[k].push_back({t.stamp, rendered.T_world_camera});
    if (t.frame_number < 40) return;
    live[k].push_back({t.stamp, t.T_world_camera});
    live_truth[k].push_back({t.stamp, rendered.T_world_camera});
  });
  SkipUnheldResult r;
  for (int k = 0; k < 2; ++k) {
    std::vector<gmc::datasets::StampedPose> trajectory;
    for (const auto& [n, pose] : written[k]) trajectory.push_back(pose);
    r.written[k] = gmc::datasets::computeAte(truth[k], trajectory).error.rmse;
    r.live[k] = gmc::datasets::computeAte(live_truth[k], live[k]).error.rmse;
  }
  return r;
}

// The estimate stood on the group walking in step for the first 15 frames; then the room
// takes over. Those first keyframes stay in the map, and as the window's fixed keyframes
// (they share the most landmarks) they pulled every new keyframe 6-17 cm back towards the
// group until they left it, 140 frames later. Their pose rested on landmarks since seen
// moving: they take no part.
TEST(OdometrySim, KeyframesPosedOnAGroupDoNotPullTheWindowBackOntoIt) {
  const SkipUnheldResult r = synchronousWithAndWithoutUnheld();
  std::printf("  synchronous seed 1, stream 2, 130 frames: ATE %.4f m written, %.4f m live (frames 40-130); with the "
              "unheld keyframes in the window %.4f / %.4f m\n", r.written[0], r.live[0], r.written[1], r.live[1]);
  EXPECT_GT(r.written[1], 0.06) << "the scenario must leave keyframes posed on the group in the map";
  EXPECT_LT(r.written[0], 0.04);
  EXPECT_LT(r.live[0], 0.8 * r.live[1]);
}

/// Tracks 45 frames of a camera among walkers, then sees `blind` blank frames while the
/// camera moves on, then the scene again; returns the frames not tracked after the
/// blind stretch and the last frame's position error.
std::pair<int, double> lostAfterBlindStretch(int walkers, int blind) {
  auto o = gmc::sim::SimOptions::exact();
  o.people.walkers = walkers;
  o.trajectory.style = "halfsphere";
  const gmc::sim::Simulator sim(o);
  gmc::vo::RgbdOdometry vo{gmc::vo::OdometryConfig{}};
  const gmc::Isometry T0_inv = sim.cameraPose(0).inverse();
  int lost_after = 0;
  double error = 0;
  for (int i = 0; i < 45 + blind + 20; ++i) {
    const auto [f, t] = trackSimFrame(sim, vo, i, i >= 45 && i < 45 + blind);
    if (i >= 45 + blind) lost_after += t.state != gmc::vo::TrackingState::Tracking;
    error = (t.T_world_camera.translation() - (T0_inv * f.T_world_camera).translation()).norm();
  }
  return {lost_after, error};
}

// After half a second of lost frames the prediction is decimetres off the camera. The
// first frames that see the scene again must be judged with a prior that widened over
// the lost frames (else only the stale prediction can win, and the landmarks that
// disagree with it make the background "untrusted"), and the step from the predicted
// pose back onto the map is a correction, not a velocity to extrapolate.
TEST(OdometrySim, TrackingResumesOnTheMapAfterABlindStretch) {
  for (int walkers : {4, 6}) {
    const auto [lost, error] = lostAfterBlindStretch(walkers, 15);
    std::printf("  %d walkers, 15 blind frames: %d of the 20 frames after them not tracked, final error %.4f m\n",
                walkers, lost, error);
    EXPECT_LE(lost, 1) << walkers << " walkers";
    EXPECT_LT(error, 0.01) << walkers << " walkers";
  }
}

// The first frame tracked after lost frames steps from a predicted pose back onto the
// map: that step corrects the prediction, it is no velocity. When that frame is also a
// keyframe (the window re-optimises it), the velocity must not be taken from it either:
// bonn_crowd_301_460 frame 152 stepped 9.6 cm after 8 lost frames and the next lost
// frames were extrapolated another 18 cm from it.
TEST(OdometrySim, ACorrectionAfterLostFramesIsNoVelocityEvenOnAKeyframe) {
  const gmc::sim::Simulator sim(emptyHalfsphere());
  gmc::vo::RgbdOdometry vo{gmc::vo::OdometryConfig{}};
  const int blind = 25;  // the camera moves on unseen: the prediction falls behind
  int i = 0;
  for (; i < 45 + blind; ++i) trackSimFrame(sim, vo, i, i >= 45);
  gmc::vo::FrameTracking back;
  for (; i < 45 + blind + 10; ++i) {
    back = trackSimFrame(sim, vo, i).tracking;
    if (back.state == gmc::vo::TrackingState::Tracking) break;
  }
  ASSERT_EQ(back.state, gmc::vo::TrackingState::Tracking) << "never tracked again";
  ASSERT_TRUE(back.new_keyframe) << "the scenario must make the correcting frame a keyframe";
  const auto next = trackSimFrame(sim, vo, i + 1, true);     // blank: its pose is the prediction
  ASSERT_EQ(next.tracking.state, gmc::vo::TrackingState::Lost);
  const double predicted_step = (next.tracking.T_world_camera.translation() - back.T_world_camera.translation()).norm();
  const double true_step = (next.rendered.T_world_camera.translation() -
                            sim.renderFrame(i).T_world_camera.translation()).norm();
  std::printf("  predicted step after the correcting keyframe %.4f m (camera %.4f m)\n", predicted_step, true_step);
  EXPECT_LT(predicted_step, 0.02);
}

/// Tracks `seen` frames of a static scene under a moving camera, then two blank frames;
/// returns how far the second lost frame's pose (predicted from the first, which was
/// predicted from a tracked frame) is from the first's.
double stepIntoALostFrame(int seen, double still_share) {
  const gmc::sim::Simulator sim(emptyHalfsphere());
  gmc::vo::OdometryConfig config;
  config.odometry.young_map_lost_still_share = still_share;
  gmc::vo::RgbdOdometry vo(config);
  for (int i = 0; i < seen; ++i)
    EXPECT_NE(trackSimFrame(sim, vo, i).tracking.state, gmc::vo::TrackingState::Lost) << i;
  const auto first = trackSimFrame(sim, vo, seen, true).tracking;
  const auto second = trackSimFrame(sim, vo, seen + 1, true).tracking;
  EXPECT_EQ(first.state, gmc::vo::TrackingState::Lost);
  EXPECT_EQ(second.state, gmc::vo::TrackingState::Lost);
  return (second.T_world_camera.translation() - first.T_world_camera.translation()).norm();
}

// Lost frames extrapolate the velocity (halved each frame), unless the map is younger
// than its static evidence (a second) and the last tracked frame saw walkers: then the
// velocity may be a walker's and the frames after the first lost one stand still. Without walkers (share 0 below the
// default 0.2) it extrapolates; with the threshold at 0 it stands still in a young map
// and extrapolates again once landmarks have static evidence.
TEST(OdometrySim, ALostFrameInAYoungMapStandsStillOnlyAfterWalkers) {
  const double young_default = stepIntoALostFrame(10, 0.2);
  const double young_always = stepIntoALostFrame(10, 0.0);
  const double old_always = stepIntoALostFrame(45, 0.0);
  std::printf("  step between two lost frames: young map %.4f m (default), %.4f m (threshold 0); "
              "evidence-holding map %.4f m (threshold 0)\n", young_default, young_always, old_always);
  EXPECT_GT(young_default, 1e-3);
  EXPECT_LT(young_always, 1e-9);
  EXPECT_GT(old_always, 1e-3);
}

/// Tracks `seen` frames of a static scene under a moving camera, then a blank frame;
/// returns that first lost frame.
gmc::vo::FrameTracking loseAfter(int seen, int unheld_start_frames, double still_share) {
  const gmc::sim::Simulator sim(emptyHalfsphere());
  gmc::vo::OdometryConfig config;
  config.odometry.young_map_lost_still_share = still_share;
  config.odometry.unheld_start_frames = unheld_start_frames;
  gmc::vo::RgbdOdometry vo(config);
  for (int i = 0; i < seen; ++i)
    EXPECT_NE(trackSimFrame(sim, vo, i).tracking.state, gmc::vo::TrackingState::Lost) << i;
  return trackSimFrame(sim, vo, seen, true).tracking;
}

// A map lost a few frames after its start, before any static evidence and with walkers
// in view (the still rule above; its share at 0 here stands in for the walkers), was
// never held by the room: its tracked frames go back to the start pose, as lost frames
// (bridged if the map holds again). Past `unheld_start_frames`, or without walkers,
// nothing is revised.
TEST(OdometrySim, AMapLostBeforeAnythingHeldItGoesBackToItsStart) {
  const auto unheld = loseAfter(6, 12, 0.0);
  ASSERT_EQ(unheld.state, gmc::vo::TrackingState::Lost);
  EXPECT_LT(unheld.T_world_camera.translation().norm(), 1e-9);  // the first frame's pose
  std::set<long> at_start;
  for (const auto& r : unheld.revised)
    if (r.T_world_camera.translation().norm() < 1e-9) at_start.insert(r.frame_number);
  EXPECT_EQ(at_start, (std::set<long>{2, 3, 4, 5, 6}));
  const auto held_longer = loseAfter(20, 12, 0.0);
  EXPECT_GT(held_longer.T_world_camera.translation().norm(), 1e-3);
  EXPECT_TRUE(held_longer.revised.empty() || held_longer.revised.back().T_world_camera.translation().norm() > 1e-3);
  const auto without_walkers = loseAfter(6, 12, 0.2);
  EXPECT_GT(without_walkers.T_world_camera.translation().norm(), 1e-3);
  const auto off = loseAfter(6, 0, 0.0);
  EXPECT_GT(off.T_world_camera.translation().norm(), 1e-3);
}

/// Keyframes whose landmarks are alive in the odometry's map, after tracking 20 frames of
/// a static scene and then frames the map cannot explain (a fresh noise image each, the
/// depth kept) until the odometry re-anchors.
std::set<int> keyframesInMapAfterReanchor(bool new_map) {
  const gmc::sim::Simulator sim(emptyHalfsphere());
  gmc::vo::OdometryConfig config;
  config.keyframes.reanchor_new_map = new_map;
  gmc::vo::RgbdOdometry vo(config);
  bool reanchored = false;
  for (int i = 0; i < 20 + config.keyframes.reanchor_after_lost && !reanchored; ++i) {
    const auto rendered = sim.renderFrame(i);
    const auto& f = rendered.frame;
    cv::Mat gray;
    cv::cvtColor(f.rgb, gray, cv::COLOR_BGR2GRAY);
    if (i >= 20) cv::randu(gray, cv::Scalar(0), cv::Scalar(256));  // cv::theRNG(): a new image each frame
    const auto t = vo.process(gray, f.depth, f.depth_units, f.camera, f.stamp);
    if (i >= 20) {
      EXPECT_NE(t.state, gmc::vo::TrackingState::Tracking) << "frame " << i;
    }
    reanchored = t.state == gmc::vo::TrackingState::Reanchored;
  }
  EXPECT_TRUE(reanchored);
  std::set<int> keyframes;
  for (size_t id = 0; id < vo.landmarks().size(); ++id)
    if (vo.landmarks()[static_cast<int>(id)].alive) keyframes.insert(vo.landmarks()[static_cast<int>(id)].keyframe);
  return keyframes;
}

// A re-anchored keyframe sits at a guessed pose, off by however far the camera moved
// unseen; the old landmarks are off by as much from it. Tracking on both slides from one
// to the other over the next seconds (stop_and_go_hover seed 1: 0.15 m while tracked with
// 20-30 static landmarks), so the keyframe starts a new local map instead.
TEST(OdometrySim, AReanchoredKeyframeStartsANewLocalMap) {
  const auto fresh = keyframesInMapAfterReanchor(true);
  ASSERT_EQ(fresh.size(), 1u);
  EXPECT_GT(*fresh.begin(), 0);  // the re-anchored keyframe's, not the first one's
  const auto joined = keyframesInMapAfterReanchor(false);
  EXPECT_GT(joined.size(), 1u);
  EXPECT_EQ(joined.count(0), 1u);
}

/// Tracks 45 frames of a static scene, then 10 frames the map cannot explain (a fresh
/// noise image each, the depth kept: the odometry re-anchors on the last one, seeding a
/// map that the real frames after it cannot match either), then real frames until the
/// odometry re-anchors again on one of them and tracks on: `each(i, rendered frame,
/// tracking)` for every frame, until it returns false.
using ReanchorStep = std::function<bool(int, const gmc::sim::SimFrame&, const gmc::vo::FrameTracking&)>;
void runTwoReanchors(const gmc::vo::OdometryConfig& config, int frames, const ReanchorStep& each) {
  const gmc::sim::Simulator sim(emptyHalfsphere());
  gmc::vo::RgbdOdometry vo(config);
  for (int i = 0; i < frames; ++i) {
    const auto rendered = sim.renderFrame(i);
    const auto& f = rendered.frame;
    cv::Mat gray;
    cv::cvtColor(f.rgb, gray, cv::COLOR_BGR2GRAY);
    if (i >= 45 && i < 55) cv::randu(gray, cv::Scalar(0), cv::Scalar(256));
    if (!each(i, rendered, vo.process(gray, f.depth, f.depth_units, f.camera, f.stamp))) break;
  }
}

/// That scenario's position error (against the truth, both relative to the first frame)
/// at the last of `frames`, and the frame that rejoined the first map (-1: none).
std::pair<double, int> errorAfterTwoReanchors(bool rejoin, int frames) {
  gmc::vo::OdometryConfig config;
  config.keyframes.reanchor_after_lost = 10;
  config.rejoin.enabled = rejoin;
  gmc::Isometry T0_inv = gmc::Isometry::Identity();
  int rejoined_at = -1;
  double error = 0;
  runTwoReanchors(config, frames, [&](int i, const gmc::sim::SimFrame& rendered, const gmc::vo::FrameTracking& t) {
    if (i == 0) T0_inv = rendered.T_world_camera.inverse();
    if (t.rejoined) rejoined_at = i;
    error = (t.T_world_camera.translation() - (T0_inv * rendered.T_world_camera).translation()).norm();
    return true;
  });
  return {error, rejoined_at};
}

// After a re-anchor every pose keeps the offset of the guessed keyframe; the old map's
// landmarks, found again over the whole image, give it back (doc/odometry.md, eleventh
// round). Without the rejoin the error stays at the offset.
TEST(OdometrySim, AReanchoredMapRejoinsTheMapItLeft) {
  const auto [kept_error, never] = errorAfterTwoReanchors(false, 110);
  const auto [error, rejoined_at] = errorAfterTwoReanchors(true, 110);
  std::printf("  after two re-anchors: error %.4f m without the rejoin, %.4f m with it (rejoined at frame %d)\n",
              kept_error, error, rejoined_at);
  EXPECT_EQ(never, -1);
  EXPECT_GT(kept_error, 0.05);
  EXPECT_GT(rejoined_at, 64);
  EXPECT_LT(error, 0.02);
}

}  // namespace

/// The crowd scenario at seed 16 over its first `frames` frames (rendered once): with and
/// without [Rejoin] young_map_anchor, the written trajectory (live poses with every
/// revision applied) against the truth, both relative to the first frame. Per run: the
/// frame that rejoined (-1: none) and the RMS position error over the frames.
struct YoungMapRun {
  int rejoined_at = -1;
  double rms = 0;
};
std::pair<YoungMapRun, YoungMapRun> crowdSeed16(int frames) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/crowd.ini";
  auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  options.simulator.seed = 16;
  const gmc::sim::Simulator sim(options);
  std::vector<gmc::sim::SimFrame> rendered;
  std::vector<cv::Mat> gray(static_cast<size_t>(frames));
  for (int i = 0; i < frames; ++i) {
    rendered.push_back(sim.renderFrame(i));
    cv::cvtColor(rendered.back().frame.rgb, gray[static_cast<size_t>(i)], cv::COLOR_BGR2GRAY);
  }
  const gmc::Isometry T0_inv = rendered.front().T_world_camera.inverse();
  auto run = [&](bool anchor) {
    gmc::vo::OdometryConfig config;
    config.rejoin.young_map_anchor = anchor;
    gmc::vo::RgbdOdometry vo(config);
    std::map<long, gmc::Isometry> written;
    YoungMapRun out;
    for (int i = 0; i < frames; ++i) {
      const auto& f = rendered[static_cast<size_t>(i)].frame;
      const auto t = vo.process(gray[static_cast<size_t>(i)], f.depth, f.depth_units, f.camera, f.stamp);
      written[t.frame_number] = t.T_world_camera;
      for (const auto& r : t.revised) written[r.frame_number] = r.T_world_camera;
      if (t.rejoined && out.rejoined_at < 0) out.rejoined_at = i;
    }
    double sum_sq = 0;
    int i = 0;
    for (const auto& [number, pose] : written) {
      const gmc::Isometry truth = T0_inv * rendered[static_cast<size_t>(i++)].T_world_camera;
      sum_sq += (pose.translation() - truth.translation()).squaredNorm();
    }
    out.rms = std::sqrt(sum_sq / static_cast<double>(written.size()));
    return out;
  };
  return {run(true), run(false)};
}

// Crowd seed 16: walkers lead the first map from its second frame on, it is lost at the
// fifth and re-anchored at the 34th at a guessed pose, 25 cm and 4 degrees off; what the
// first map froze is walkers, which the old rejoin never finds. Its first keyframe, seen
// before anything misled it, is found on the new map's room: the new map moves into the
// first one's frame and the young map's frames are bridged (doc/odometry.md, fifty-fourth
// round).
TEST(OdometrySim, AYoungMapLeftAmongWalkersIsFoundByItsFirstKeyframe) {
  const auto [with, without] = crowdSeed16(130);
  std::printf("  crowd seed 16, 130 frames: position error RMS %.4f m with the young map's anchor (rejoined at "
              "frame %d), %.4f m without (rejoined at %d)\n", with.rms, with.rejoined_at, without.rms,
              without.rejoined_at);
  EXPECT_EQ(without.rejoined_at, -1);
  EXPECT_GT(without.rms, 0.1);
  EXPECT_GT(with.rejoined_at, 34);
  EXPECT_LT(with.rms, 0.03);
}

/// Blind frames 45..45+blind-1 of the half-sphere scene, then frames until one is tracked:
/// per blind frame its live pose, its revised pose (if any) and the truth, all relative to
/// frame 0. Returns false if tracking never resumed.
struct BlindFrame {
  double stamp = 0;
  gmc::Isometry live, truth;
  std::optional<gmc::Isometry> revised;
};
bool bridgeBlindStretch(bool revise, int blind, std::vector<BlindFrame>& frames) {
  const gmc::sim::Simulator sim(emptyHalfsphere());
  gmc::vo::OdometryConfig config;
  config.odometry.revise_lost = revise;
  gmc::vo::RgbdOdometry vo(config);
  const gmc::Isometry T0_inv = sim.cameraPose(0).inverse();
  for (int i = 0; i < 45 + blind + 10; ++i) {
    const auto [f, t] = trackSimFrame(sim, vo, i, i >= 45 && i < 45 + blind);
    if (i >= 45 && t.state == gmc::vo::TrackingState::Lost)
      frames.push_back({t.stamp, t.T_world_camera, T0_inv * f.T_world_camera, std::nullopt});
    for (const auto& r : t.revised)
      for (auto& b : frames)
        if (b.stamp == r.stamp) b.revised = r.T_world_camera;
    if (i >= 45 + blind && t.state == gmc::vo::TrackingState::Tracking) return true;
  }
  return false;
}

// A lost frame's pose is the prediction, given out live. Once a frame is tracked on the
// same map again, the lost ones are revised onto the path between the two tracked poses:
// for a camera that moves on smoothly that is far closer than the prediction, which
// halves the velocity every frame and falls behind. The half-sphere path curves, so the
// straight path between the two ends of half a second is centimetres off it.
TEST(OdometrySim, LostFramesAreRevisedOntoThePathOnceTrackingResumes) {
  std::vector<BlindFrame> frames;
  ASSERT_TRUE(bridgeBlindStretch(true, 15, frames)) << "never tracked again";
  ASSERT_GE(frames.size(), 15u);
  double live = 0, revised = 0;
  for (const auto& b : frames) {
    ASSERT_TRUE(b.revised.has_value()) << "lost frame at " << b.stamp << " not revised";
    live = std::max(live, (b.live.translation() - b.truth.translation()).norm());
    revised = std::max(revised, (b.revised->translation() - b.truth.translation()).norm());
  }
  std::printf("  15 blind frames: worst position error %.4f m live (predicted), %.4f m revised\n", live, revised);
  EXPECT_LT(revised, 0.05);
  EXPECT_LT(revised, 0.5 * live);

  std::vector<BlindFrame> unrevised;
  ASSERT_TRUE(bridgeBlindStretch(false, 15, unrevised));
  for (const auto& b : unrevised) EXPECT_FALSE(b.revised.has_value()) << "revise_lost=false revised a pose";
}

/// runTwoReanchors's scenario with the rejoin on: the worst position error over the
/// frames of the map that is rejoined (from its re-anchored frame to the frame before the
/// rejoin), as the trajectory holds them once the revisions are applied.
double worstErrorOfTheRejoinedMap(bool revise) {
  gmc::vo::OdometryConfig config;
  config.keyframes.reanchor_after_lost = 10;
  config.odometry.revise_lost = revise;
  gmc::Isometry T0_inv = gmc::Isometry::Identity();
  std::vector<gmc::Isometry> poses, truth;
  std::vector<long> numbers;
  int reanchored_at = -1, rejoined_at = -1;
  runTwoReanchors(config, 110, [&](int i, const gmc::sim::SimFrame& rendered, const gmc::vo::FrameTracking& t) {
    if (i == 0) T0_inv = rendered.T_world_camera.inverse();
    poses.push_back(t.T_world_camera);
    truth.push_back(T0_inv * rendered.T_world_camera);
    numbers.push_back(t.frame_number);
    for (const auto& r : t.revised)
      for (size_t k = 0; k < numbers.size(); ++k)
        if (numbers[k] == r.frame_number) poses[k] = r.T_world_camera;
    if (t.state == gmc::vo::TrackingState::Reanchored) reanchored_at = i;
    if (t.rejoined) rejoined_at = i;
    return rejoined_at < 0;
  });
  EXPECT_GT(rejoined_at, reanchored_at);
  EXPECT_GT(reanchored_at, 55);  // the second re-anchor, on a real frame
  double worst = 0;
  for (int k = reanchored_at; k < rejoined_at; ++k)
    worst = std::max(worst, (poses[static_cast<size_t>(k)].translation() - truth[static_cast<size_t>(k)].translation()).norm());
  return worst;
}

// The map re-anchored at a guessed pose carries the guess's offset until it is rejoined
// to the map it left; then its frames are known in the old map's frame too, and the
// trajectory holds them there (doc/odometry.md, sixteenth round).
TEST(OdometrySim, ARejoinRevisesTheFramesOfTheMapItBringsBack) {
  const double live = worstErrorOfTheRejoinedMap(false), revised = worstErrorOfTheRejoinedMap(true);
  std::printf("  frames of the rejoined map: worst error %.4f m as given out, %.4f m revised\n", live, revised);
  EXPECT_GT(live, 0.05);
  EXPECT_LT(revised, 0.02);
}

// [Odometry] random_seed gives other RANSAC sampling streams: the run changes (else the
// key would measure nothing), and the crowd bound above holds for them too (a bound that
// held for one stream only would be luck).
TEST(OdometrySim, TheCrowdBoundHoldsForOtherSamplingStreams) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/crowd.ini";
  const auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  const gmc::sim::Simulator sim(options);
  const gmc::Isometry T0_inv = sim.cameraPose(0).inverse();
  const int frames = 80;
  std::vector<gmc::sim::SimFrame> rendered;  // rendered once: the renderer is the slow part
  std::vector<cv::Mat> gray(frames);
  for (int i = 0; i < frames; ++i) {
    rendered.push_back(sim.renderFrame(i));
    cv::cvtColor(rendered.back().frame.rgb, gray[static_cast<size_t>(i)], cv::COLOR_BGR2GRAY);
  }
  std::vector<std::vector<Eigen::Vector3d>> positions;
  for (int seed : {0, 1, 2}) {
    gmc::vo::OdometryConfig config;
    config.odometry.random_seed = seed;
    gmc::vo::RgbdOdometry vo(config);
    double sum_sq = 0;
    positions.emplace_back();
    for (int i = 0; i < frames; ++i) {
      const auto& r = rendered[static_cast<size_t>(i)];
      const auto t = vo.process(gray[static_cast<size_t>(i)], r.frame.depth, r.frame.depth_units, r.frame.camera,
                                r.frame.stamp);
      positions.back().push_back(t.T_world_camera.translation());
      sum_sq += (t.T_world_camera.translation() - (T0_inv * r.T_world_camera).translation()).squaredNorm();
    }
    const double rms = std::sqrt(sum_sq / frames);
    std::printf("  crowd, %d frames, random_seed %d: position error RMS %.4f m\n", frames, seed, rms);
    EXPECT_LT(rms, 0.03) << "random_seed " << seed;
  }
  for (size_t s = 1; s < positions.size(); ++s) {
    double largest = 0;
    for (int i = 0; i < frames; ++i)
      largest = std::max(largest, (positions[s][static_cast<size_t>(i)] - positions[0][static_cast<size_t>(i)]).norm());
    EXPECT_GT(largest, 1e-6) << "random_seed " << s << " ran exactly as seed 0";
  }
}

namespace {

/// Of the landmarks keyframes created on people (by the simulator's mask at the pixel
/// that placed them) and on the room, the share that started suspect.
struct IntakeShares {
  double people = 0, room = 0;
  int people_count = 0, room_count = 0;
};
/// The keyframe that made the newest landmarks (origin_stamp would also name a suspect
/// landmark re-placed where it was seen this frame).
int newestKeyframe(const gmc::vo::LandmarkMap& map) {
  int newest = -1;
  for (size_t id = 0; id < map.size(); ++id)
    if (map[static_cast<int>(id)].alive) newest = std::max(newest, map[static_cast<int>(id)].keyframe);
  return newest;
}

/// With `masked`, each frame's dynamic mask is built after the odometry and handed back to
/// it, as the gmc filter does.
IntakeShares suspectShareAtCreation(const gmc::sim::SimOptions& options, const gmc::vo::OdometryConfig& config,
                                    int frames, bool masked = false) {
  const gmc::sim::Simulator sim(options);
  gmc::vo::RgbdOdometry vo(config);
  gmc::vo::DynamicMaskBuilder mask_builder;
  int suspect[2] = {0, 0}, total[2] = {0, 0};
  for (int i = 0; i < frames; ++i) {
    const auto [f, t] = trackSimFrame(sim, vo, i);
    if (masked) vo.distrustMaskedLandmarks(mask_builder.build(t, f.frame.depth, f.frame.depth_units, f.frame.camera));
    if (!t.new_keyframe) continue;
    const auto& map = vo.landmarks();
    const int newest = newestKeyframe(map);
    for (size_t id = 0; id < map.size(); ++id) {
      const auto& l = map[static_cast<int>(id)];
      if (!l.alive || l.keyframe != newest) continue;  // made by this keyframe
      const Eigen::Vector2d uv = f.frame.camera.project(l.origin_point);
      const int u = std::clamp(static_cast<int>(std::lround(uv.x())), 0, f.mask.cols - 1);
      const int v = std::clamp(static_cast<int>(std::lround(uv.y())), 0, f.mask.rows - 1);
      const int person = f.mask.at<std::uint8_t>(v, u) > 0 ? 1 : 0;
      ++total[person];
      suspect[person] += map.evidence(static_cast<int>(id), f.frame.stamp) == gmc::vo::Evidence::Suspect;
    }
  }
  return {static_cast<double>(suspect[1]) / std::max(1, total[1]), static_cast<double>(suspect[0]) / std::max(1, total[0]),
          total[1], total[0]};
}

void printIntake(const IntakeShares& without, const IntakeShares& with) {
  std::printf("  new landmarks starting suspect, people / room: %.2f / %.2f (%d / %d) off, %.2f / %.2f (%d / %d) on\n",
              without.people, without.room, without.people_count, without.room_count, with.people, with.room,
              with.people_count, with.room_count);
}

}  // namespace

// [Odometry] track_frames (off by default; doc/odometry.md, thirty-second round): a
// keyframe's new landmark whose frame-to-frame track moved on in the world starts
// suspect. On the crowd scenario that reaches more of the landmarks made on people than
// GMC's label alone, and none more of the room's. Few new landmarks have a track of 3
// frames or more (walkers' corners are rarely matched from frame to frame for long), so
// the share moves by a few points: off 0.06 / 0.01, on 0.10 / 0.00 over 60 frames.
TEST(OdometrySim, TracksThatMovedOnMakeTheWalkersNewLandmarksStartSuspect) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/crowd.ini";
  const auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  gmc::vo::OdometryConfig off, on;
  on.odometry.track_frames = 8;
  on.odometry.track_min_dynamic_share = 0;  // every keyframe once the start is judged
  const IntakeShares without = suspectShareAtCreation(options, off, 60);
  const IntakeShares with = suspectShareAtCreation(options, on, 60);
  printIntake(without, with);
  ASSERT_GT(with.people_count, 50);
  EXPECT_GT(with.people, without.people + 0.015);
  EXPECT_LT(with.room, without.room + 0.01);
}

// [Odometry] mask_new_landmarks (off by default; doc/odometry.md, thirty-third round): a
// keyframe's new landmark inside the frame's dynamic mask (GMC's dynamic keypoints grown
// over continuous depth, and free space) starts suspect. The mask reaches the walkers'
// corners that GMC leaves undecided, and few of the room's (60 frames: people 0.06 -> 0.69,
// room 0.01 -> 0.02).
TEST(OdometrySim, TheDynamicMaskMakesTheWalkersNewLandmarksStartSuspect) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/crowd.ini";
  const auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  gmc::vo::OdometryConfig off, on;
  on.odometry.mask_new_landmarks = true;
  on.odometry.mask_min_dynamic_share = 0;  // every keyframe once the start is judged
  on.odometry.mask_min_static_landmarks = 0;
  const IntakeShares without = suspectShareAtCreation(options, off, 60, true);
  const IntakeShares with = suspectShareAtCreation(options, on, 60, true);
  printIntake(without, with);
  ASSERT_GT(with.people_count, 50);
  EXPECT_GT(with.people, 0.5);  // off: 0.06 (GMC's dynamic label alone)
  EXPECT_LT(with.room, 0.1);
}

// The mask judges only new landmarks in front of the points that hold the pose
// ([Odometry] mask_front_margin): walkers pass in front of the room, and a pose that
// follows walkers would otherwise mask the room behind them. And only where landmarks
// with static evidence hold the pose (mask_min_static_landmarks): the mask is drawn with
// it. A mask that covers the whole image leaves the far half of each keyframe's new
// landmarks trusted, and all of them before the map has static evidence.
TEST(OdometrySim, TheMaskJudgesOnlyNewLandmarksInFrontOfAPoseHeldByStaticEvidence) {
  gmc::vo::OdometryConfig config;
  config.odometry.mask_new_landmarks = true;
  config.odometry.mask_min_dynamic_share = 0;
  const gmc::sim::Simulator sim(emptyHalfsphere());
  gmc::vo::RgbdOdometry vo(config);
  int judged_keyframes = 0, suspect = 0, trusted = 0, suspect_behind = 0, unjudged_keyframes = 0,
      suspect_unjudged = 0;
  for (int i = 0; i < 80; ++i) {
    const auto [f, t] = trackSimFrame(sim, vo, i);
    vo.distrustMaskedLandmarks(cv::Mat(f.frame.depth.size(), CV_8UC1, cv::Scalar(255)));
    if (!t.new_keyframe || t.state != gmc::vo::TrackingState::Tracking) continue;
    std::vector<double> suspect_depth, trusted_depth;
    const auto& map = vo.landmarks();
    const int newest = newestKeyframe(map);
    for (size_t id = 0; id < map.size(); ++id) {
      const auto& l = map[static_cast<int>(id)];
      if (!l.alive || l.keyframe != newest) continue;
      const bool distrusted = map.evidence(static_cast<int>(id), f.frame.stamp) == gmc::vo::Evidence::Suspect;
      (distrusted ? suspect_depth : trusted_depth).push_back(l.origin_point.z());
    }
    if (t.static_landmarks_matched < config.odometry.mask_min_static_landmarks) {
      ++unjudged_keyframes;
      suspect_unjudged += static_cast<int>(suspect_depth.size());
      continue;
    }
    if (suspect_depth.empty() || trusted_depth.empty()) continue;
    ++judged_keyframes;
    suspect += static_cast<int>(suspect_depth.size());
    trusted += static_cast<int>(trusted_depth.size());
    const double nearest_trusted = *std::min_element(trusted_depth.begin(), trusted_depth.end());
    for (double z : suspect_depth) suspect_behind += z > nearest_trusted;
  }
  std::printf("  %d keyframes judged: %d new landmarks suspect, %d trusted, %d suspect behind a trusted one; "
              "%d keyframes before static evidence: %d suspect\n",
              judged_keyframes, suspect, trusted, suspect_behind, unjudged_keyframes, suspect_unjudged);
  ASSERT_GE(judged_keyframes, 2);
  ASSERT_GE(unjudged_keyframes, 1);
  EXPECT_EQ(suspect_unjudged, 0);
  EXPECT_GT(trusted, suspect);  // the median splits the pose's points, most new ones are behind it
  EXPECT_EQ(suspect_behind, 0);  // GMC labels nothing dynamic on this empty scene
}

namespace {

/// Over `frames` frames of a scenario: keypoints that held a tracked pose while lying on
/// a person of the generator's mask; the masks given to the odometry as known dynamic
/// pixels or not.
int posePointsOnPeople(const gmc::sim::SimOptions& options, int frames, bool known) {
  const gmc::sim::Simulator sim(options);
  gmc::vo::RgbdOdometry vo;
  int on_people = 0;
  for (int i = 0; i < frames; ++i) {
    const auto rendered = sim.renderFrame(i);
    const auto& f = rendered.frame;
    cv::Mat gray;
    cv::cvtColor(f.rgb, gray, cv::COLOR_BGR2GRAY);
    const auto t = vo.process(gray, f.depth, f.depth_units, f.camera, f.stamp, known ? rendered.mask : cv::Mat());
    for (size_t k = 0; k < t.keypoints.size(); ++k) {
      const cv::Point p(cvRound(t.keypoints[k].x), cvRound(t.keypoints[k].y));
      on_people += t.keypoint_in_pose[k] && rendered.mask.at<std::uint8_t>(p) > 0;
    }
  }
  return on_people;
}

}  // namespace

// Known dynamic pixels (RgbdOdometry::process's last argument: a person segmenter's
// output; here the generator's masks): no keypoint on them holds a pose, where GMC alone
// lets some through in a hovering crowd.
TEST(OdometrySim, KnownDynamicPixelsNeverHoldThePose) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/crowd_hover.ini";
  const auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  const int without = posePointsOnPeople(options, 40, false), with = posePointsOnPeople(options, 40, true);
  std::printf("  crowd_hover, 40 frames: pose points on people %d with GMC alone, %d with known masks\n", without,
              with);
  EXPECT_GT(without, 0);
  EXPECT_EQ(with, 0);
}

// [FreeSpace] (off by default; doc/odometry.md, thirty-eighth round): a keyframe's new
// landmark where four views 0.3-2 s old saw the room farther behind starts suspect.
// Walkers step into space the camera has seen empty; the room's corners are never in
// front of what was seen there (only pose error at a depth edge puts them so).
TEST(OdometrySim, FreeSpaceSeenBeforeMakesTheWalkersNewLandmarksStartSuspect) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/crowd.ini";
  const auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  gmc::vo::OdometryConfig off, on;
  on.free_space.enabled = true;
  const IntakeShares without = suspectShareAtCreation(options, off, 60);
  const IntakeShares with = suspectShareAtCreation(options, on, 60);
  printIntake(without, with);
  ASSERT_GT(with.people_count, 50);
  EXPECT_GT(with.people, without.people + 0.1);
  EXPECT_LT(with.room, without.room + 0.01);
}

// [DepthAlignment] (off by default; doc/odometry.md, thirty-ninth round): the last tracked
// frame's depth, as planes, joins the pose. On the crowd scenario's first 60 frames
// (walkers on a third of the image, their untextured parts unmarked by keypoints) the
// run stays within centimetres, as the keypoints alone do, and the term pulls the pose
// (its weight changes the run).
TEST(OdometrySim, TheRoomsDepthInThePoseKeepsTheCrowdWithinCentimetres) {
  const std::string path = GMC_SOURCE_DIR "/config/sim/crowd.ini";
  const auto options = gmc::sim::loadSimOptions(gmc::cfg::loadIniFile(path), path);
  double rms_keypoints = 0;
  worstError(options, {}, 60, nullptr, &rms_keypoints);
  gmc::vo::OdometryConfig dense;
  dense.depth_alignment.enabled = true;
  dense.depth_alignment.weight = 0.03;
  double rms = 0;
  int lost = 0;
  const double worst = worstError(options, dense, 60, &lost, &rms);
  std::printf("  crowd, 60 frames: position error RMS %.4f m with the room's depth (worst %.4f, %d lost), %.4f "
              "without\n",
              rms, worst, lost, rms_keypoints);
  EXPECT_LT(rms, 0.05);
  EXPECT_LT(rms, 1.5 * rms_keypoints);
  gmc::vo::OdometryConfig other_weight = dense;
  other_weight.depth_alignment.weight = 1.0;
  EXPECT_NE(worstError(options, other_weight, 30), worstError(options, dense, 30));
}

// The trajectory's smoothing gives a frame's pose smoothing_frames frames later; at the
// input's end finish() gives the last ones, fitted over the run's last full window, so
// no frame of a tracked input keeps its live pose in the trajectory.
TEST(OdometrySim, TheInputsLastFramesAreSmoothedWhenItEnds) {
  auto o = gmc::sim::SimOptions::exact();
  o.people.walkers = 0;
  o.trajectory.style = "xyz";
  const gmc::sim::Simulator sim(o);
  gmc::vo::OdometryConfig config;
  ASSERT_TRUE(config.odometry.smoothing_edges);
  const int k = config.odometry.smoothing_frames, frames = 30;
  ASSERT_GT(k, 0);
  gmc::vo::RgbdOdometry vo(config);
  std::vector<long> numbers;
  std::vector<gmc::Isometry> live;
  std::set<long> revised;
  for (int i = 0; i < frames; ++i) {
    const auto t = trackSimFrame(sim, vo, i).tracking;
    ASSERT_NE(t.state, gmc::vo::TrackingState::Lost) << "frame " << i;
    numbers.push_back(t.frame_number);
    live.push_back(t.T_world_camera);
    for (const auto& r : t.revised) revised.insert(r.frame_number);
  }
  // Before the end every tracked frame but the last k was revised (the first ones from
  // the run's first window), and none of the last k; frame 0 initialises the map.
  for (int i = 1; i < frames; ++i)
    EXPECT_EQ(revised.count(numbers[static_cast<size_t>(i)]), i < frames - k ? 1u : 0u) << "frame " << i;
  const auto last = vo.finish();
  ASSERT_EQ(last.size(), static_cast<size_t>(k));
  for (int j = 0; j < k; ++j) {
    const size_t i = static_cast<size_t>(frames - k + j);
    EXPECT_EQ(last[static_cast<size_t>(j)].frame_number, numbers[i]);
    // A fit over tracked poses that move millimetres a frame stays near them.
    EXPECT_LT((last[static_cast<size_t>(j)].T_world_camera.translation() - live[i].translation()).norm(), 0.01);
  }
  EXPECT_TRUE(vo.finish().empty()) << "a second end gives nothing more";
}
