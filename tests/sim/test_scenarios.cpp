// The hard scenarios of config/sim/ (crowd, person_tracking, synchronous, close_pass):
// their ground truth and the properties their INI comments promise.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/imgproc.hpp>

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "sim_test_helpers.h"

namespace {

using gmc::sim::SimOptions;
using gmc::sim::Simulator;

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(p / 100.0 * static_cast<double>(v.size() - 1) + 0.5)];
}

double peopleShare(const cv::Mat& mask) { return cv::countNonZero(mask) / static_cast<double>(mask.total()); }

/// Share of the image on people in every `step`-th frame.
std::vector<double> coverage(const Simulator& sim, int step) {
  std::vector<double> out;
  for (int i = 0; i < sim.frameCount(); i += step) out.push_back(peopleShare(sim.renderFrame(i).mask));
  return out;
}

/// An empty office seen by a static camera, noise-free.
SimOptions emptyOffice() {
  SimOptions o = SimOptions::exact();
  o.trajectory.style = "static";
  o.people.walkers = 0;
  o.room.style = "office";
  return o;
}

/// GFTT corners of the first frame (quality relative to the frame's strongest corner)
/// whose image row satisfies `in_rows`.
template <class RowTest>
long cornersIn(const SimOptions& o, double quality, double min_distance, RowTest in_rows) {
  cv::Mat gray;
  cv::cvtColor(Simulator(o).renderFrame(0).frame.rgb, gray, cv::COLOR_BGR2GRAY);
  std::vector<cv::Point2f> c;
  cv::goodFeaturesToTrack(gray, c, 5000, quality, min_distance);
  return static_cast<long>(std::count_if(c.begin(), c.end(), [&](const cv::Point2f& p) { return in_rows(p.y / gray.rows); }));
}

TEST(Scenarios, NoiseFreeStaticPixelsReprojectExactly) {
  for (const char* name : {"crowd", "person_tracking", "synchronous", "close_pass"}) {
    SimOptions o = small(scenario(name));
    o.sensor = SimOptions::exact().sensor;
    // A pair of frames 14 apart where the static scene shows (close_pass starts behind a person).
    const Simulator sim(o);
    int i = 3;
    while (peopleShare(sim.renderFrame(i).mask) > 0.4 || peopleShare(sim.renderFrame(i + 14).mask) > 0.4) i += 5;
    expectStaticPixelsReprojectExactly(o, name, i, i + 14);
  }
}

TEST(Scenarios, CrowdCoversAQuarterOfTheImageInTheMedianFrameAndHalfAtP90) {
  for (int seed : {1, 2, 3}) {
    SimOptions o = small(scenario("crowd"));
    o.simulator.seed = seed;
    const Simulator sim(o);
    const auto share = coverage(sim, 3);
    const double p50 = percentile(share, 50), p90 = percentile(share, 90);
    std::printf("  crowd seed %d: people on %.3f of the pixels (p50), %.3f (p90)\n", seed, p50, p90);
    EXPECT_GE(p50, 0.25) << "seed " << seed;
    EXPECT_GE(p90, 0.50) << "seed " << seed;
  }
}

TEST(Scenarios, SomeoneInTheCrowdPassesWithinOneMetre) {
  const Simulator sim(small(scenario("crowd")));
  double nearest = 1e9;
  for (int i = 0; i < sim.frameCount(); i += 3) {
    const auto f = sim.renderFrame(i);
    double lo = 0;
    cv::minMaxLoc(f.true_depth, &lo, nullptr, nullptr, nullptr, f.mask);
    if (cv::countNonZero(f.mask) > 0) nearest = std::min(nearest, lo);
  }
  EXPECT_LT(nearest, 1.0);
}

TEST(Scenarios, PersonTrackingKeepsTheFollowedWalkerNearTheCentreAt1To2Metres) {
  for (int seed : {1, 2}) {
    SimOptions o = scenario("person_tracking");
    o.simulator.seed = seed;
    const Simulator sim(o);
    double worst_u = 0, worst_v = 0, nearest = 1e9, farthest = 0;
    for (int i = 0; i < sim.frameCount(); ++i) {
      const double t = i / o.simulator.fps;
      const Eigen::Vector3d chest = sim.peoplePositions(t).front() + Eigen::Vector3d(0, 0, 1.25);
      const Eigen::Vector3d c = sim.cameraPose(i).inverse() * chest;
      worst_u = std::max(worst_u, std::abs(o.camera.fx * c.x() / c.z() + o.camera.cx - o.camera.width / 2.0));
      worst_v = std::max(worst_v, std::abs(o.camera.fy * c.y() / c.z() + o.camera.cy - o.camera.height / 2.0));
      nearest = std::min(nearest, c.norm()), farthest = std::max(farthest, c.norm());
    }
    std::printf("  seed %d: followed walker's chest at most %.0f px (u), %.0f px (v) from the centre, %.2f-%.2f m\n",
                seed, worst_u, worst_v, nearest, farthest);
    EXPECT_LT(worst_u, 0.15 * o.camera.width);
    EXPECT_LT(worst_v, 0.25 * o.camera.height);
    EXPECT_GE(nearest, 1.0);
    EXPECT_LE(farthest, 2.0);
  }
}

TEST(Scenarios, SynchronousGroupMovesWithTheCamera) {
  const SimOptions o = scenario("synchronous");
  const Simulator sim(o);
  const size_t first_in_group = static_cast<size_t>(o.people.walkers);
  const double dt = 1.0 / o.simulator.fps;
  double worst = 0, camera_speed = 0;
  for (int i = 0; i + 1 < sim.frameCount(); ++i) {
    const Eigen::Vector3d camera_step = sim.cameraPose(i + 1).translation() - sim.cameraPose(i).translation();
    const auto a = sim.peoplePositions(i * dt), b = sim.peoplePositions((i + 1) * dt);
    ASSERT_EQ(a.size(), first_in_group + static_cast<size_t>(o.people.group));
    for (size_t k = first_in_group; k < a.size(); ++k)
      worst = std::max(worst, ((b[k] - a[k]) - camera_step).norm() / dt);
    camera_speed = std::max(camera_speed, camera_step.norm() / dt);
  }
  std::printf("  camera up to %.2f m/s; group velocity differs from it by at most %.2g m/s\n", camera_speed, worst);
  EXPECT_GT(camera_speed, 0.5);
  EXPECT_LT(worst, 1e-6);
}

TEST(Scenarios, ClosePassFillsSixtyPercentOfTheViewForTenFrames) {
  for (int seed : {1, 2}) {
    SimOptions o = small(scenario("close_pass"));
    o.simulator.seed = seed;
    const auto share = coverage(Simulator(o), 1);
    const auto filled = std::count_if(share.begin(), share.end(), [](double s) { return s >= 0.6; });
    std::printf("  close_pass seed %d: %ld frames with people on >= 60 %% of the view\n", seed, static_cast<long>(filled));
    EXPECT_GE(filled, 10) << "seed " << seed;
  }
}

TEST(Scenarios, StopAndGoWalkersStandStillInViewThenWalkOn) {
  const SimOptions o = scenario("stop_and_go");
  ASSERT_GT(o.people.pause_min, 0);
  const Simulator sim(o);
  const double dt = 1.0 / o.simulator.fps;
  const auto steps = static_cast<int>(30.0 / dt);  // 30 s: every walker passes at least once
  std::vector<double> longest_stand(static_cast<size_t>(o.people.walkers), 0), stand(longest_stand);
  std::vector<double> fastest(longest_stand);
  for (int i = 0; i < steps; ++i) {
    const auto a = sim.peoplePositions(i * dt), b = sim.peoplePositions((i + 1) * dt);
    for (size_t k = 0; k < stand.size(); ++k) {
      const double speed = (b[k] - a[k]).norm() / dt;
      fastest[k] = std::max(fastest[k], speed);
      stand[k] = speed < 1e-9 ? stand[k] + dt : 0;
      longest_stand[k] = std::max(longest_stand[k], stand[k]);
    }
  }
  for (size_t k = 0; k < stand.size(); ++k) {
    std::printf("  walker %zu: stands up to %.1f s, walks up to %.2f m/s\n", k, longest_stand[k], fastest[k]);
    EXPECT_GE(longest_stand[k], o.people.pause_min - 2 * dt) << "walker " << k;
    EXPECT_LE(longest_stand[k], o.people.pause_max + 2 * dt) << "walker " << k;
    EXPECT_GE(fastest[k], o.people.speed_min - 1e-6) << "walker " << k;
  }
}

TEST(Scenarios, HoveringCameraMovesAsLittleAsTheBonnCamera) {
  // Bonn's crowd windows: 2.1-2.7 mm and 0.37-0.42 deg per frame (median over the frames'
  // ground truth, doc/sim.md); stop_and_go's camera moves 5.7 mm and 0.17 deg.
  const auto median_steps = [](const Simulator& sim, double fps) {
    std::vector<double> translation, rotation;
    for (int i = 0; i + 1 < 300; ++i) {
      const auto step = sim.cameraPoseAt(i / fps).inverse() * sim.cameraPoseAt((i + 1) / fps);
      translation.push_back(step.translation().norm());
      rotation.push_back(Eigen::AngleAxisd(step.linear()).angle() * 180 / M_PI);
    }
    return std::make_pair(percentile(translation, 50), percentile(rotation, 50));
  };
  const SimOptions hover = scenario("stop_and_go_hover");
  const auto [t_hover, r_hover] = median_steps(Simulator(hover), hover.simulator.fps);
  const SimOptions walking = scenario("stop_and_go");
  const auto [t_walking, r_walking] = median_steps(Simulator(walking), walking.simulator.fps);
  std::printf("  per frame: hovering %.1f mm %.2f deg, stop_and_go %.1f mm %.2f deg\n", t_hover * 1e3, r_hover,
              t_walking * 1e3, r_walking);
  EXPECT_GT(t_hover, 0.0018);
  EXPECT_LT(t_hover, 0.0030);
  EXPECT_GT(r_hover, 0.32);
  EXPECT_LT(r_hover, 0.52);
  EXPECT_GT(t_walking, 2 * t_hover);
  // The same people as stop_and_go: only the camera differs.
  EXPECT_EQ(hover.people.walkers, walking.people.walkers);
  EXPECT_EQ(hover.people.pause_max, walking.people.pause_max);
}

// crowd_hover is stop_and_go_hover's hovering camera, room and sensor with Bonn's three
// people, who never stand: its poses rest on the furniture, as Bonn's (doc/sim.md).
TEST(Scenarios, CrowdHoverFilmsThreePeopleWhoNeverStand) {
  const SimOptions o = scenario("crowd_hover"), hover = scenario("stop_and_go_hover");
  EXPECT_EQ(o.people.walkers, 3);
  EXPECT_EQ(o.trajectory.style, hover.trajectory.style);
  EXPECT_EQ(o.trajectory.amplitude, hover.trajectory.amplitude);
  EXPECT_EQ(o.trajectory.rotation, hover.trajectory.rotation);
  EXPECT_EQ(o.sensor.disparity_step, hover.sensor.disparity_step);
  EXPECT_EQ(o.room.floor, hover.room.floor);
  const Simulator sim(o);
  const double dt = 1.0 / o.simulator.fps;
  for (int i = 0; i < 300; ++i) {
    const auto a = sim.peoplePositions(i * dt), b = sim.peoplePositions((i + 1) * dt);
    ASSERT_EQ(a.size(), 3u);
    for (size_t k = 0; k < a.size(); ++k) ASSERT_GT((b[k] - a[k]).norm(), 1e-4) << "walker " << k << " frame " << i;
  }
}

// A map that starts inside the crowd: people cover most of the first frame, so the first
// keyframe's corners are mostly on them (Bonn 301_460's window +20 starts that way).
TEST(Scenarios, CrowdStartFillsTheFirstFrameWithPeople) {
  const SimOptions o = scenario("crowd_start"), hover = scenario("crowd_hover");
  EXPECT_EQ(o.people.walkers, 5);
  EXPECT_EQ(o.trajectory.amplitude, hover.trajectory.amplitude);
  EXPECT_EQ(o.sensor.disparity_step, hover.sensor.disparity_step);
  for (int seed : {1, 2, 3}) {
    SimOptions s = o;
    s.simulator.seed = seed;
    const auto first = Simulator(s).renderFrame(0);
    const double share = static_cast<double>(cv::countNonZero(first.mask)) / first.mask.total();
    std::printf("  crowd_start seed %d: people on %.3f of the first frame\n", seed, share);
    EXPECT_GE(share, 0.3) << "seed " << seed;
  }
}

// Real people who stop are never still: they shift their weight, turn and gesture, a few
// millimetres per frame, slow enough to pass a per-frame motion test as background (the
// Bonn crowd's standing people do). With fidget the standing walker's silhouette changes
// every frame, far less than while walking; without it the stand is frozen.
TEST(Scenarios, FidgetingPeopleMoveSlowlyWhileTheyStand) {
  const SimOptions shipped = scenario("stop_and_go_hover");
  ASSERT_TRUE(shipped.people.fidget);
  SimOptions o = small(shipped);
  o.trajectory.style = "static";
  o.people.walkers = 1;
  o.sensor = SimOptions::exact().sensor;
  const double dt = 1.0 / o.simulator.fps;
  // The walker's first stand of more than 2.5 s, seen from the static camera.
  const Simulator probe(o);
  int first = -1, last = -1;
  for (int i = 0, since = -1; i < 900 && last < 0; ++i) {
    const bool still = (probe.peoplePositions((i + 1) * dt)[0] - probe.peoplePositions(i * dt)[0]).norm() < 1e-9;
    if (still && since < 0) since = i;
    if (!still && since >= 0) {
      if ((i - since) * dt > 2.5) first = since, last = i;
      since = -1;
    }
  }
  ASSERT_GT(last, 0) << "no stand found";
  // Mask change between consecutive frames, as a share of the person's pixels.
  const auto change = [&](bool fidget, int from, int to) {
    SimOptions p = o;
    p.people.fidget = fidget;
    p.simulator.frames = to + 2;
    const Simulator sim(p);
    double sum = 0;
    int n = 0;
    for (int i = from; i < to; ++i) {
      const cv::Mat a = sim.renderFrame(i).mask, b = sim.renderFrame(i + 1).mask;
      if (cv::countNonZero(a) < 50) continue;
      cv::Mat x;
      cv::bitwise_xor(a, b, x);
      sum += cv::countNonZero(x) / static_cast<double>(cv::countNonZero(a));
      ++n;
    }
    return n ? sum / n : -1.0;
  };
  const int mid_from = first + 35, mid_to = last - 35;  // past the second of easing in and out
  ASSERT_GT(mid_to, mid_from + 5);
  const double frozen = change(false, mid_from, mid_to), fidgeting = change(true, mid_from, mid_to);
  const double walking = change(true, last + 5, last + 25);
  std::printf("  stand of %.1f s: silhouette change per frame frozen %.4f, fidgeting %.4f, walking %.4f\n",
              (last - first) * dt, frozen, fidgeting, walking);
  ASSERT_GE(frozen, 0.0);
  ASSERT_GE(walking, 0.0) << "the walker leaves the view";
  EXPECT_EQ(frozen, 0.0);
  EXPECT_GT(fidgeting, 0.005);
  EXPECT_LT(fidgeting, 0.5 * walking);
}

TEST(Scenarios, PlainOfficeFloorOffersFewerCornersThanTheSpeckledOne) {
  SimOptions o = emptyOffice();
  o.trajectory.tilt = 12;
  // The bottom fifth of a camera tilted down sees floor only.
  const auto bottom_fifth = [](double row) { return row > 0.8; };
  const long speckle = cornersIn(o, 0.005, 10, bottom_fifth);
  o.room.floor = "plain";
  const long plain = cornersIn(o, 0.005, 10, bottom_fifth);
  std::printf("  GFTT corners in the bottom fifth: speckled floor %ld, plain floor %ld\n", speckle, plain);
  EXPECT_LT(plain * 3, speckle);
}

TEST(Scenarios, SameSeedSameFramesWhateverTheThreads) {
  SimOptions o = small(scenario("crowd"));
  o.simulator.threads = 1;
  const Simulator one(o);
  o.simulator.threads = 3;
  const Simulator three(o);
  o.simulator.seed = 2;
  const Simulator other(o);
  for (int i : {5, 77}) {
    const auto a = one.renderFrame(i), b = three.renderFrame(i), c = other.renderFrame(i);
    EXPECT_EQ(cv::norm(a.frame.rgb, b.frame.rgb, cv::NORM_INF), 0) << i;
    EXPECT_EQ(cv::norm(a.frame.depth, b.frame.depth, cv::NORM_INF), 0) << i;
    EXPECT_EQ(cv::norm(a.mask, b.mask, cv::NORM_INF), 0) << i;
    EXPECT_GT(cv::norm(a.frame.rgb, c.frame.rgb, cv::NORM_L1), 0) << i;
  }
}

TEST(Scenarios, ProjectorShadowsLeaveDepthHolesLeftOfPeopleOnly) {
  SimOptions o = SimOptions::exact();
  o.trajectory.style = "static";
  o.people = scenario("crowd").people;
  o.sensor.projector_baseline = 0.075;
  const Simulator sim(o);
  const double fb = o.camera.fx * o.sensor.projector_baseline;
  int left_holes = 0, right_holes = 0, silhouettes = 0;
  for (int i : {10, 60, 110}) {
    const auto f = sim.renderFrame(i);
    for (int v = 0; v < f.mask.rows; ++v)
      for (int u = 3; u + 3 < f.mask.cols; ++u) {
        const auto m = [&](int x) { return f.mask.at<std::uint8_t>(v, x) != 0; };
        const auto z = [&](int x) { return f.true_depth.at<double>(v, x); };
        // A person's left edge in front of a surface far enough behind for a shadow
        // band of 3 px or more: the pixel 2 px left of the edge must have no depth.
        if (!m(u - 1) && !m(u - 3) && m(u) && fb * (1 / z(u) - 1 / z(u - 3)) >= 3) {
          ++silhouettes;
          left_holes += f.frame.depth.at<std::uint16_t>(v, u - 2) == 0;
        }
        if (m(u) && !m(u + 1) && z(u + 3) > z(u) + 0.5) right_holes += f.frame.depth.at<std::uint16_t>(v, u + 2) == 0;
      }
  }
  std::printf("  %d left silhouettes: background 2 px left has no depth at %d; 2 px right of right edges: %d\n",
              silhouettes, left_holes, right_holes);
  ASSERT_GT(silhouettes, 50);
  EXPECT_EQ(left_holes, silhouettes);
  // Right of a person only where another person's shadow falls (crowds overlap).
  EXPECT_LT(right_holes * 10, left_holes);
}

TEST(Scenarios, MotionBlurChangesColoursOnlyNearMovingPeople) {
  SimOptions o = small(SimOptions::exact());
  o.trajectory.style = "static";
  o.people = scenario("crowd").people;
  SimOptions blurred = o;
  blurred.sensor.exposure = 0.03;
  const Simulator sharp_sim(o), blur_sim(blurred);
  int changed = 0, changed_far = 0;
  for (int i : {20, 90}) {
    const auto sharp = sharp_sim.renderFrame(i), blur = blur_sim.renderFrame(i);
    EXPECT_EQ(cv::norm(sharp.frame.depth, blur.frame.depth, cv::NORM_INF), 0);  // depth of the frame's instant
    cv::Mat near_people;
    cv::dilate(sharp.mask, near_people, cv::Mat(), cv::Point(-1, -1), 6);
    cv::Mat diff;
    cv::absdiff(sharp.frame.rgb, blur.frame.rgb, diff);
    cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
    changed += cv::countNonZero(diff > 1);
    changed_far += cv::countNonZero((diff > 1) & (near_people == 0));
  }
  std::printf("  %d pixels changed by blur, %d of them away from people\n", changed, changed_far);
  EXPECT_GT(changed, 100);
  EXPECT_EQ(changed_far, 0);
}

TEST(Scenarios, OfficeWallsAreBareAboveTheFurniture) {
  SimOptions o = emptyOffice();
  // Counted in the top third: above the furniture there is only wall.
  const auto top_third = [](double row) { return row < 1.0 / 3; };
  const long office = cornersIn(o, 0.01, 5, top_third);
  o.room.style = "tiles";
  const long tiles = cornersIn(o, 0.01, 5, top_third);
  std::printf("  GFTT corners in the top third: office %ld, tiled room %ld\n", office, tiles);
  EXPECT_LT(office * 5, tiles);
}

TEST(Scenarios, InconsistentNewKeysAreNamedErrors) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[People]\ngroup = 2\n", "group"},
      {"[Trajectory]\nstyle = follow\n[People]\nwalkers = 0\n", "follow"},
      {"[Room]\nstyle = castle\n", "style"},
      {"[Room]\nwindows = 3\n", "windows"},
      {"[People]\nclothes = fur\n", "clothes"},
      {"[People]\npause_min = 3\npause_max = 2\n", "pause_min"},
      {"[Room]\nfloor = carpet\n", "floor"},
      {"[Sensor]\nblur_samples = 1\n", "blur_samples"},
  };
  for (const auto& [text, key] : cases) {
    const mrpt::config::CConfigFileMemory ini(text);
    try {
      gmc::sim::loadSimOptions(ini, "test.ini");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const gmc::cfg::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("test.ini"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
