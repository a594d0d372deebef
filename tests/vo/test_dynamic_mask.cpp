#include <gtest/gtest.h>

#include "gmc/sim/simulator.h"
#include "gmc/vo/dynamic_mask.h"

namespace {

using gmc::vo::DynamicMaskBuilder;
using gmc::vo::DynamicMaskOptions;

/// A tracked frame at a known pose, without keypoints: only the free-space check can
/// mark anything.
gmc::vo::FrameTracking trackedAt(const gmc::Isometry& T_world_camera) {
  gmc::vo::FrameTracking t;
  t.state = gmc::vo::TrackingState::Tracking;
  t.T_world_camera = T_world_camera;
  return t;
}

struct PixelScore {
  double tp = 0, fp = 0, fn = 0, pixels = 0;
  double precision() const { return tp + fp > 0 ? tp / (tp + fp) : 1.0; }
  double recall() const { return tp + fn > 0 ? tp / (tp + fn) : 1.0; }
};

/// Masks of simulated frames (sensor noise on) at the ground-truth poses, scored against
/// the simulator's person masks from frame `skip` on (the history fills first).
PixelScore scoreFreeSpaceMasks(gmc::sim::SimOptions o, int frames, int skip) {
  o.simulator.frames = frames;
  const gmc::sim::Simulator sim(o);
  DynamicMaskBuilder builder;
  PixelScore s;
  for (int i = 0; i < frames; ++i) {
    const auto f = sim.renderFrame(i);
    const cv::Mat mask = builder.build(trackedAt(f.T_world_camera), f.frame.depth, f.frame.depth_units,
                                       f.frame.camera);
    if (i < skip) continue;
    for (int v = 0; v < mask.rows; ++v)
      for (int u = 0; u < mask.cols; ++u) {
        if (f.frame.depth.at<std::uint16_t>(v, u) == 0) continue;
        const bool predicted = mask.at<std::uint8_t>(v, u) > 0, person = f.mask.at<std::uint8_t>(v, u) > 0;
        s.tp += predicted && person, s.fp += predicted && !person, s.fn += !predicted && person;
        ++s.pixels;
      }
  }
  return s;
}

TEST(DynamicMask, MovingCameraInAStaticSceneGivesNoFreeSpaceEvidence) {
  gmc::sim::SimOptions o;  // sensor noise, dropout and quantisation on
  o.people.walkers = 0;
  for (const char* style : {"rpy", "halfsphere"}) {
    o.trajectory.style = style;
    const PixelScore s = scoreFreeSpaceMasks(o, 20, 0);
    std::printf("  %s, no people: %.0f of %.0f pixels marked dynamic\n", style, s.fp, s.pixels);
    EXPECT_LT(s.fp, 1e-3 * s.pixels) << style;
  }
}

TEST(DynamicMask, FreeSpaceEvidenceFindsWalkersWithoutAnyKeypoint) {
  gmc::sim::SimOptions o;
  o.people.walkers = 3;
  for (const char* style : {"xyz"}) {
    o.trajectory.style = style;
    const PixelScore s = scoreFreeSpaceMasks(o, 50, 30);
    std::printf("  %s, 3 walkers, frames 30-49: precision %.3f recall %.3f\n", style, s.precision(), s.recall());
    EXPECT_GT(s.tp, 0);
    EXPECT_GT(s.precision(), 0.85) << style;
    EXPECT_GT(s.recall(), 0.8) << style;
  }
}

TEST(DynamicMask, FreeSpaceCheckOffOrLostFramesAddNothing) {
  gmc::sim::SimOptions o;
  o.people.walkers = 3;
  o.trajectory.style = "static";
  o.simulator.frames = 20;
  const gmc::sim::Simulator sim(o);
  DynamicMaskOptions off;
  off.free_space_check = false;
  DynamicMaskBuilder without(off), lost_frames;
  int marked_without = 0, marked_lost = 0;
  for (int i = 0; i < 20; ++i) {
    const auto f = sim.renderFrame(i);
    marked_without += cv::countNonZero(
        without.build(trackedAt(f.T_world_camera), f.frame.depth, f.frame.depth_units, f.frame.camera));
    auto lost = trackedAt(f.T_world_camera);
    lost.state = gmc::vo::TrackingState::Lost;  // a lost frame's pose is only predicted
    marked_lost += cv::countNonZero(lost_frames.build(lost, f.frame.depth, f.frame.depth_units, f.frame.camera));
    EXPECT_TRUE(lost_frames.lastViolations().empty());
  }
  EXPECT_EQ(marked_without, 0);
  EXPECT_EQ(marked_lost, 0);
}

TEST(DynamicMask, AnObjectAppearingInFrontOfAWallIsMaskedAndTheWallIsNot) {
  // Hand-made depth: a wall at 3 m; from frame 5 on a 100 x 100 px box at 1.5 m.
  gmc::PinholeCamera camera;
  DynamicMaskBuilder builder;
  const double units = 1.0 / 5000.0;
  const cv::Rect box(270, 190, 100, 100);
  cv::Mat mask;
  for (int i = 0; i < 8; ++i) {
    cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(3.0 / units));
    if (i >= 5) depth(box).setTo(1.5 / units);
    mask = builder.build(trackedAt(gmc::Isometry::Identity()), depth, units, camera);
    if (i < 5) {
      EXPECT_EQ(cv::countNonZero(mask), 0) << "frame " << i;
    }
  }
  const cv::Rect inner(box.x + 8, box.y + 8, box.width - 16, box.height - 16);
  EXPECT_EQ(cv::countNonZero(mask(inner)), inner.area());
  cv::Mat outside = mask.clone();
  outside(cv::Rect(box.x - 12, box.y - 12, box.width + 24, box.height + 24)).setTo(0);
  EXPECT_EQ(cv::countNonZero(outside), 0);
}

}  // namespace
