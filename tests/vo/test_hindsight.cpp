#include <gtest/gtest.h>

#include <random>

#include "gmc/vo/hindsight.h"
#include "seen_features.h"

namespace {

using gmc::Isometry;
using gmc::test::randomDescriptor;
using gmc::test::SeenFeatures;
using gmc::vo::HindsightFrame;
using gmc::vo::HindsightOptions;
using gmc::vo::HindsightPoser;
using gmc::vo::Landmark;
using gmc::vo::LandmarkMap;
using gmc::vo::RevisedPose;

const gmc::PinholeCamera kCamera{};  // TUM fr3, 640x480
constexpr double kStep = 0.05;       // m per frame: the camera walks sideways, fast
constexpr int kLag = 5;

/// n points of a room 2.5-4 m ahead, spread over x in [x0, x1] (world frame).
std::vector<Landmark> points(int n, double x0, double x1, std::mt19937& rng) {
  std::uniform_real_distribution<double> x(x0, x1), y(-1.0, 1.0), z(2.5, 4.0);
  std::vector<Landmark> out(static_cast<size_t>(n));
  for (auto& l : out) {
    l.position = Eigen::Vector3d(x(rng), y(rng), z(rng));
    l.descriptor = randomDescriptor(rng);
  }
  return out;
}

Isometry truePose(int frame) {
  Isometry T = Isometry::Identity();
  T.translation() = Eigen::Vector3d(kStep * frame, 0, 0);
  return T;
}

/// The features a camera at T_world_camera sees: the room points in view, and a group
/// walking in step with it (`group`: their positions in the camera's frame).
gmc::features::FeatureSet frame(const std::vector<Landmark>& room, const std::vector<Landmark>& group,
                                const Isometry& T_world_camera) {
  SeenFeatures seen(kCamera);
  for (const auto& l : room) seen.add(T_world_camera.inverse() * l.position, l.descriptor);
  for (const auto& l : group) seen.add(l.position, l.descriptor);
  return seen.take();
}

struct Scene {
  std::mt19937 rng{11};
  std::vector<Landmark> mapped_room, unmapped_room, group;
  LandmarkMap map;
  std::vector<int> group_ids;  ///< the group's landmarks in the map: they held the given poses

  /// mapped_room: the room points the map holds today; unmapped_room: room points no
  /// landmark stands for (seen by the frames, matched only frame to frame).
  explicit Scene(int unmapped) {
    mapped_room = points(150, -1.5, 1.5, rng);
    unmapped_room = points(unmapped, -1.5, 1.5, rng);
    group = points(80, -0.8, 0.8, rng);  // camera frame: they walk with it
    for (auto& l : group) l.position.z() -= 1.0;
    map.adopt(mapped_room);
    const int first_group = static_cast<int>(map.size());
    map.adopt(group);
    for (int i = 0; i < static_cast<int>(group.size()); ++i) group_ids.push_back(first_group + i);
  }
  /// What frame k sees of the room: before frame `mapped_from`, only 15 of the mapped points
  /// (fewer than a judgement needs), from it on all of them.
  std::vector<Landmark> room(int k, int mapped_from) const {
    std::vector<Landmark> all = unmapped_room;
    all.insert(all.end(), mapped_room.begin(), k >= mapped_from ? mapped_room.end() : mapped_room.begin() + 15);
    return all;
  }
};

/// Frames 0..frames-1 of a camera walking kStep a frame, given out standing still (on the
/// group), fed to `hindsight` with today's view at the true pose. Returns every revision.
std::vector<RevisedPose> walk(HindsightPoser& hindsight, const Scene& scene, int frames, int mapped_from = 0,
                              bool landmarks_dropped = false, int lost_frame = -1) {
  const gmc::features::Frontend frontend;
  std::vector<RevisedPose> revisions;
  for (int k = 0; k < frames; ++k) {
    HindsightFrame f{k,
                     k / 30.0,
                     frame(scene.room(k, mapped_from), scene.group, truePose(k)),
                     Isometry::Identity(),
                     landmarks_dropped ? std::vector<int>(scene.group_ids.size(), -1) : scene.group_ids,
                     k == lost_frame};
    for (const auto& r : hindsight.add(std::move(f), scene.map, truePose(k), kCamera, frontend, 6.0))
      revisions.push_back(r);
  }
  return revisions;
}

HindsightOptions options() {
  HindsightOptions o;
  o.lag_frames = kLag;
  return o;
}

HindsightPoser poser(const HindsightOptions& o = options()) {
  return HindsightPoser(o, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
}

/// The group's landmarks, which held the given poses, have been seen moving since.
void groupSeenMoving(Scene& scene) {
  for (int id : scene.group_ids) scene.map.distrust(id, 0.0);
}

std::vector<long> frameNumbers(const std::vector<RevisedPose>& revisions) {
  std::vector<long> out;
  for (const auto& r : revisions) out.push_back(r.frame_number);
  return out;
}

std::vector<long> framesFrom(long first, long last) {
  std::vector<long> out;
  for (long k = first; k <= last; ++k) out.push_back(k);
  return out;
}

// The given poses stood still on a group walking with the camera; the group's landmarks
// have since been seen moving and the map holds the room. Each pose, judged kLag frames
// later on the room, goes back onto the camera's path.
TEST(HindsightPoser, APoseThatRestedOnLandmarksSeenMovingIsPosedOnTheRoom) {
  Scene scene(0);
  groupSeenMoving(scene);
  auto hindsight = poser();
  const auto revisions = walk(hindsight, scene, 15);
  // Frames 1-9 (judged at 6-14); frame 0 was given where the camera was (within min_shift).
  ASSERT_EQ(revisions.size(), 15u - kLag - 1);
  for (const auto& r : revisions) {
    const Isometry truth = truePose(static_cast<int>(r.frame_number));
    EXPECT_LT((r.T_world_camera.translation() - truth.translation()).norm(), 0.005) << r.frame_number;
  }
  EXPECT_EQ(revisions.front().frame_number, 1);
}

// The same frames, but the group's landmarks are still trusted: what held the poses has not
// been seen moving, and nothing is judged again.
TEST(HindsightPoser, APoseStillHeldByTrustedLandmarksStays) {
  Scene scene(0);
  auto hindsight = poser();
  EXPECT_TRUE(walk(hindsight, scene, 15).empty());
}

// Landmarks dropped since (culled when no longer found) say nothing about what held a pose.
TEST(HindsightPoser, LandmarksDroppedSinceSayNothing) {
  Scene scene(0);
  groupSeenMoving(scene);
  auto hindsight = poser();
  EXPECT_TRUE(walk(hindsight, scene, 15, 0, true).empty());
}

// The early frames see mostly a part of the room that no landmark stands for (the mapped
// part came into view at frame kLag) and cannot be judged on their own. Once frame kLag is
// posed on the map, they are posed back from it, frame by frame, on the room it found (as
// far back as the kLag frames kept after their own judgement).
TEST(HindsightPoser, FramesBeforeARevisedOneArePosedBackFromIt) {
  Scene scene(120);
  groupSeenMoving(scene);
  auto hindsight = poser();
  const auto revisions = walk(hindsight, scene, 2 * kLag + 1, kLag);
  for (const auto& r : revisions) {
    const Isometry truth = truePose(static_cast<int>(r.frame_number));
    EXPECT_LT((r.T_world_camera.translation() - truth.translation()).norm(), 0.01) << r.frame_number;
  }
  // Frame kLag and, posed back from it, the frames down to 1 (frame 0 was given where the
  // camera was).
  EXPECT_EQ(frameNumbers(revisions), framesFrom(1, kLag));
}

// A lost frame has no measured pose to judge, and posing lost frames one from the next
// follows what made them lost: it ends what is posed back (the bridging of lost stretches
// puts them on the path).
TEST(HindsightPoser, ALostFrameIsNeitherJudgedNorPosedThrough) {
  Scene scene(120);
  groupSeenMoving(scene);
  auto hindsight = poser();
  EXPECT_EQ(frameNumbers(walk(hindsight, scene, 2 * kLag + 1, kLag, false, 2)), framesFrom(3, kLag));
}

// A new world frame (a new map, a start consensus, a rejoin) ends what can be compared.
TEST(HindsightPoser, AResetForgetsTheFramesKept) {
  Scene scene(0);
  groupSeenMoving(scene);
  auto hindsight = poser();
  walk(hindsight, scene, kLag);
  EXPECT_EQ(hindsight.kept(), static_cast<size_t>(kLag));
  hindsight.reset();
  EXPECT_EQ(hindsight.kept(), 0u);
  HindsightOptions off = options();
  off.enabled = false;
  auto disabled = poser(off);
  EXPECT_TRUE(walk(disabled, scene, 15).empty());
  EXPECT_EQ(disabled.kept(), 0u);
}

}  // namespace
