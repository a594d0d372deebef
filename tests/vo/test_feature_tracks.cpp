#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "gmc/vo/feature_tracks.h"

namespace {

using gmc::Isometry;
using gmc::features::FeatureMatch;
using gmc::features::FeatureSet;
using gmc::vo::FeatureTracks;

/// A frame of keypoints at the given camera-frame points (z = 0: no depth).
FeatureSet frameAt(const std::vector<Eigen::Vector3d>& points) {
  FeatureSet set;
  set.points = points;
  set.keypoints.resize(points.size());
  return set;
}

/// Keypoint i of the last frame is keypoint i of this one.
std::vector<FeatureMatch> sameOrder(size_t n) {
  std::vector<FeatureMatch> matches;
  for (size_t i = 0; i < n; ++i) matches.push_back({static_cast<int>(i), static_cast<int>(i), 0});
  return matches;
}

/// A camera sliding 3 cm a frame sideways: what stands still in the world moves in the image.
Isometry cameraAt(int frame) {
  Isometry T = Isometry::Identity();
  T.translation() = Eigen::Vector3d(0.03 * frame, 0, 0);
  return T;
}

TEST(FeatureTracks, AWalkerMovesOnWhileTheWallAndAJitteringCornerDoNot) {
  // Keypoint 0: a wall point at 3 m. 1: a walker at 2 m going 2 cm a frame (GMC's
  // interval at 2 m is 2 cm with alpha = 100: frame by frame it may pass for static). 2: a corner on a depth edge whose reading flips between 1.5 and 3 m every other frame.
  // 3: a wall point with 1 cm of depth noise.
  FeatureTracks tracks(8);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (int f = 0; f < 8; ++f) {
    const Isometry T_world_camera = cameraAt(f);
    const Isometry T_camera_world = T_world_camera.inverse();
    const Eigen::Vector3d wall(0.2, 0.1, 3.0), walker(-0.3 + 0.02 * f, 0.0, 2.0), edge(0.5, -0.2, f % 2 ? 1.5 : 3.0);
    const Eigen::Vector3d noisy = T_camera_world * Eigen::Vector3d(-0.4, 0.3, 3.0) + Eigen::Vector3d(0, 0, noise(rng));
    tracks.extend(frameAt({T_camera_world * wall, T_camera_world * walker, T_camera_world * edge, noisy}),
                  sameOrder(4), T_world_camera, true);
  }
  EXPECT_EQ(tracks.positions(1), 8);
  EXPECT_LT(tracks.movedOn(0), 1e-9);
  EXPECT_NEAR(tracks.movedOn(1), 0.12, 1e-9);  // halves of 4 and 3 steps: the shorter, doubled
  EXPECT_EQ(tracks.movedOn(2), 0.0);            // jumps back and forth
  EXPECT_LT(tracks.movedOn(3), 0.05);
}

TEST(FeatureTracks, TracksKeepTheLastPositionsAndStartOverWhenTheyBreak) {
  FeatureTracks tracks(4);
  const Eigen::Vector3d moving_step(0.05, 0, 0);
  for (int f = 0; f < 10; ++f)
    tracks.extend(frameAt({Eigen::Vector3d(0, 0, 2) + f * moving_step, Eigen::Vector3d(0, 0, 2)}), sameOrder(2),
                  Isometry::Identity(), true);
  EXPECT_EQ(tracks.positions(0), 4);
  EXPECT_NEAR(tracks.movedOn(0), 0.10, 1e-9);  // halves of the last 4: 2 steps, then 1 step (doubled)

  // Unmatched, the keypoint starts a new track; so does one that loses its depth.
  std::vector<FeatureMatch> only_second = {{1, 1, 0}};
  tracks.extend(frameAt({Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(0, 0, 0)}), only_second, Isometry::Identity(), true);
  EXPECT_EQ(tracks.positions(0), 1);
  EXPECT_EQ(tracks.positions(1), 0);
  EXPECT_EQ(tracks.movedOn(0), 0.0);

  // A frame that does not continue the poses before it starts every track over.
  tracks.extend(frameAt({Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(0, 0, 2)}), sameOrder(2), Isometry::Identity(), true);
  EXPECT_EQ(tracks.positions(0), 2);
  tracks.extend(frameAt({Eigen::Vector3d(0, 0, 2), Eigen::Vector3d(0, 0, 2)}), sameOrder(2), Isometry::Identity(), false);
  EXPECT_EQ(tracks.positions(0), 1);
  EXPECT_EQ(tracks.positions(1), 1);
}

TEST(FeatureTracks, OffKeepsNothing) {
  FeatureTracks tracks(0);
  EXPECT_FALSE(tracks.enabled());
  for (int f = 0; f < 5; ++f)
    tracks.extend(frameAt({Eigen::Vector3d(0.1 * f, 0, 2)}), sameOrder(1), Isometry::Identity(), true);
  EXPECT_EQ(tracks.positions(0), 0);
  EXPECT_EQ(tracks.movedOn(0), 0.0);
}

}  // namespace
