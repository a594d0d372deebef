#include <gtest/gtest.h>

#include <cstdint>

#include "gmc/vo/free_space.h"

namespace {

using gmc::Isometry;
using gmc::PinholeCamera;
using gmc::vo::FreeSpaceHistory;
using gmc::vo::FreeSpaceOptions;

constexpr double kUnits = 1.0 / 5000;  // TUM's depth scale

/// A frontal wall `wall_m` away, optionally with a hole (no reading) in a square.
cv::Mat wallDepth(double wall_m, cv::Rect hole = cv::Rect()) {
  cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(static_cast<std::uint16_t>(wall_m / kUnits)));
  if (hole.area() > 0) depth(hole).setTo(0);
  return depth;
}

FreeSpaceOptions enabled() {
  FreeSpaceOptions o;
  o.enabled = true;
  return o;
}

Isometry cameraAtX(double x) {
  Isometry T = Isometry::Identity();
  T.translation().x() = x;
  return T;
}

TEST(FreeSpaceHistory, APointInFrontOfAWallSeenBeforeWasSeenThrough) {
  FreeSpaceHistory history(enabled());
  const PinholeCamera camera;
  for (int k = 0; k < 5; ++k) history.push(wallDepth(3.0), kUnits, cameraAtX(0.01 * k), 0.2 * k);
  // A walker's corner 2 m away (in front of the wall 3 m away): all five views saw the wall.
  EXPECT_EQ(history.seenThrough({0.1, 0.0, 2.0}, camera, 1.0), 5);
  // Only views taken before `before` count.
  EXPECT_EQ(history.seenThrough({0.1, 0.0, 2.0}, camera, 0.3), 2);
  // On the wall, behind it, or in front of it within the depth margin: never seen through.
  EXPECT_EQ(history.seenThrough({0.1, 0.0, 3.0}, camera, 1.0), 0);
  EXPECT_EQ(history.seenThrough({0.1, 0.0, 4.0}, camera, 1.0), 0);
  EXPECT_EQ(history.seenThrough({0.1, 0.0, 2.9}, camera, 1.0), 0);
  // Behind the cameras, or outside their images: no view decides.
  EXPECT_EQ(history.seenThrough({0.1, 0.0, -2.0}, camera, 1.0), 0);
  EXPECT_EQ(history.seenThrough({5.0, 0.0, 2.0}, camera, 1.0), 0);
}

TEST(FreeSpaceHistory, AMissingReadingOrANearerSurfaceAroundThePixelDecidesNothing) {
  FreeSpaceHistory history(enabled());
  const PinholeCamera camera;
  // A hole in the depth around the image centre, and a post 1 m away just left of it.
  cv::Mat depth = wallDepth(3.0, cv::Rect(310, 238, 20, 20));
  depth(cv::Rect(200, 200, 40, 80)).setTo(static_cast<std::uint16_t>(1.0 / kUnits));
  history.push(depth, kUnits, Isometry::Identity(), 0.0);
  const auto at = [&](double u, double v, double z) { return camera.unproject(u, v, z); };
  EXPECT_EQ(history.seenThrough(at(320, 248, 2.0), camera, 1.0), 0);  // in the hole
  EXPECT_EQ(history.seenThrough(at(243, 240, 2.0), camera, 1.0), 0);  // beside the post's edge
  EXPECT_EQ(history.seenThrough(at(260, 240, 2.0), camera, 1.0), 1);  // clear of both
}

TEST(FreeSpaceHistory, KeepsViewsApartAndForgetsOldOnes) {
  FreeSpaceOptions o = enabled();
  o.spacing_seconds = 0.1;
  o.history_seconds = 1.0;
  FreeSpaceHistory history(o);
  const PinholeCamera camera;
  // 30 frames a second for 2 s: a view every 0.1 s at most, the last second's only.
  for (int k = 0; k < 60; ++k) history.push(wallDepth(3.0), kUnits, Isometry::Identity(), k / 30.0);
  const int seen = history.seenThrough({0.0, 0.0, 2.0}, camera, 10.0);
  EXPECT_GE(seen, 9);
  EXPECT_LE(seen, 11);
  history.clear();
  EXPECT_EQ(history.seenThrough({0.0, 0.0, 2.0}, camera, 10.0), 0);
}

TEST(FreeSpaceHistory, APointArrivedWhenEnoughViewsOldEnoughSawThrough) {
  FreeSpaceOptions o = enabled();
  o.min_views = 3;
  o.min_age_seconds = 0.5;
  FreeSpaceHistory history(o);
  const PinholeCamera camera;
  for (int k = 0; k <= 5; ++k) history.push(wallDepth(3.0), kUnits, Isometry::Identity(), 0.25 * k);
  // Views at 0-1.25 s; at 1 s those up to 0.5 s count (three), at 0.75 s two.
  EXPECT_TRUE(history.arrivedSince({0.0, 0.0, 2.0}, camera, 1.0));
  EXPECT_FALSE(history.arrivedSince({0.0, 0.0, 2.0}, camera, 0.75));
  EXPECT_FALSE(history.arrivedSince({0.0, 0.0, 3.0}, camera, 1.0));
}

TEST(FreeSpaceHistory, ADisabledHistoryKeepsNoViewAndFlagsNothing) {
  FreeSpaceOptions o = enabled();
  o.enabled = false;
  o.min_views = 1;
  o.min_age_seconds = 0;
  FreeSpaceHistory history(o);
  const PinholeCamera camera;
  for (int k = 0; k < 5; ++k) history.push(wallDepth(3.0), kUnits, Isometry::Identity(), 0.25 * k);
  EXPECT_EQ(history.seenThrough({0.0, 0.0, 2.0}, camera, 10.0), 0);
  EXPECT_FALSE(history.arrivedSince({0.0, 0.0, 2.0}, camera, 10.0));
}

}  // namespace
