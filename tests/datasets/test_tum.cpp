#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "gmc/datasets/camera.h"
#include "gmc/datasets/tum.h"
#include "test_data.h"

namespace {

using namespace gmc::datasets;

std::string writeFile(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(Associate, GreedyByTimeDifferenceEachStampOnce) {
  // The closest pair (1.000, 1.004) goes first; 1.012's nearest (1.004) is then taken,
  // so it gets 0.995 (0.017 < 0.02). 2.0 has no partner.
  const auto m = associate({1.000, 1.012, 2.0}, {0.995, 1.004, 3.0}, 0.02);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0], (std::pair<size_t, size_t>(0, 1)));
  EXPECT_EQ(m[1], (std::pair<size_t, size_t>(1, 0)));
}

TEST(Associate, EdgeCases) {
  EXPECT_TRUE(associate({}, {1.0}).empty());
  EXPECT_TRUE(associate({1.0}, {}).empty());
  EXPECT_TRUE(associate({1.0}, {1.02}).empty());           // exactly max_dt: not associated
  EXPECT_EQ(associate({1.0}, {1.0199}).size(), 1u);
  const auto unsorted = associate({3.0, 1.0, 2.0}, {2.001, 0.999, 3.002});
  ASSERT_EQ(unsorted.size(), 3u);  // result sorted by the first list's stamps
  EXPECT_EQ(unsorted[0].first, 1u);
  EXPECT_EQ(unsorted[0].second, 1u);
  EXPECT_EQ(unsorted[2].first, 0u);
}

TEST(TumFiles, ListsAndTrajectoriesRoundTrip) {
  const auto dir = gmc::testdata::scratchDir("tum_roundtrip");
  writeTumList(dir + "/rgb.txt", {{1.5, "rgb/1.5.png"}, {1.533333, "rgb/b.png"}}, "test");
  const auto list = readTumList(dir + "/rgb.txt");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_DOUBLE_EQ(list[1].stamp, 1.533333);
  EXPECT_EQ(list[1].path, "rgb/b.png");

  StampedPose p;
  p.stamp = 1305031102.175304;
  p.pose.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  p.pose.translation() = Eigen::Vector3d(1.25, -0.5, 2.0);
  writeTumTrajectory(dir + "/t.txt", {p});
  const auto back = readTumTrajectory(dir + "/t.txt");
  ASSERT_EQ(back.size(), 1u);
  EXPECT_NEAR(back[0].stamp, p.stamp, 1e-6);
  EXPECT_TRUE(back[0].pose.isApprox(p.pose, 1e-7));
}

TEST(TumFiles, MalformedInputNamesFileAndLine) {
  const auto dir = gmc::testdata::scratchDir("tum_bad");
  const auto list = writeFile(dir, "rgb.txt", "# comment\n1.0 rgb/a.png\n2.0\n");
  EXPECT_EQ(errorOf([&] { readTumList(list); }), list + ":3: expected 'timestamp filename'");
  const auto back = writeFile(dir, "back.txt", "2.0 a.png\n1.0 b.png\n");
  EXPECT_EQ(errorOf([&] { readTumList(back); }), back + ":2: timestamps go backwards");
  const auto traj = writeFile(dir, "t.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 x 0 0 0 1\n");
  EXPECT_EQ(errorOf([&] { readTumTrajectory(traj); }),
            traj + ":2: expected 'timestamp tx ty tz qx qy qz qw'");
  const auto quat = writeFile(dir, "q.txt", "1.0 0 0 0 0 0 0 2\n");
  EXPECT_EQ(errorOf([&] { readTumTrajectory(quat); }), quat + ":1: quaternion is not unit length");
  // Fuzz finding: a coordinate like -2e260 overflowed the ATE alignment (NaN errors).
  const auto far = writeFile(dir, "far.txt", "1.0 0 0 0 0 0 0 1\n2.0 -2e260 0 0 0 0 0 1\n");
  EXPECT_EQ(errorOf([&] { readTumTrajectory(far); }), far + ":2: position beyond 1e9 m");
  const auto utm = writeFile(dir, "utm.txt", "1.0 500000.5 5400000.25 310 0 0 0 1\n");
  EXPECT_DOUBLE_EQ(readTumTrajectory(utm).at(0).pose.translation().y(), 5400000.25);
  EXPECT_EQ(errorOf([&] { readTumList(dir + "/missing.txt"); }), dir + "/missing.txt: cannot open");
}

TEST(TumFiles, CommaSeparatedTrajectoriesAreRead) {
  const auto dir = gmc::testdata::scratchDir("tum_comma");
  const auto t = writeFile(dir, "t.txt", "1.0,1,2,3,0,0,0,1\n");
  const auto poses = readTumTrajectory(t);
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_DOUBLE_EQ(poses[0].pose.translation().z(), 3.0);
}

TEST(Camera, PresetsAndExplicitValues) {
  EXPECT_DOUBLE_EQ(cameraPreset("fr3").fx, 535.4);
  EXPECT_DOUBLE_EQ(cameraPreset("fr1").cy, 255.3);
  EXPECT_DOUBLE_EQ(cameraPreset("bonn").fx, 542.822841);
  const auto c = cameraPreset("500,501,320.5,240.5");
  EXPECT_DOUBLE_EQ(c.fy, 501);
  EXPECT_THROW(cameraPreset("fr4"), std::invalid_argument);
  EXPECT_THROW(cameraPreset("500,501,320"), std::invalid_argument);
  EXPECT_THROW(cameraPreset("500,-1,320,240"), std::invalid_argument);
}

TEST(Interpolate, SlerpBetweenPosesAndNothingOutside) {
  StampedPose a, b;
  a.stamp = 1.0;
  b.stamp = 1.08;
  b.pose.translation() = Eigen::Vector3d(1, 0, 0);
  b.pose.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto mid = interpolatePose({a, b}, 1.04);
  ASSERT_TRUE(mid.has_value());
  EXPECT_NEAR(mid->translation().x(), 0.5, 1e-9);
  EXPECT_NEAR(Eigen::AngleAxisd(mid->linear()).angle(), 0.1, 1e-9);
  EXPECT_FALSE(interpolatePose({a, b}, 2.0).has_value());
  EXPECT_FALSE(interpolatePose({}, 1.0).has_value());
}

}  // namespace
