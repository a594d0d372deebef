#include <gtest/gtest.h>

#include <random>

#include "gmc/vo/map_rejoin.h"
#include "seen_features.h"

namespace {

using gmc::Isometry;
using gmc::test::randomDescriptor;
using gmc::test::SeenFeatures;
using gmc::vo::Landmark;
using gmc::vo::MapRejoin;
using gmc::vo::RejoinAttempt;
using gmc::vo::RejoinOptions;

const gmc::PinholeCamera kCamera{};  // TUM fr3, 640x480

/// n landmarks of a room 2-4 m in front of the old world's origin, each with its own
/// descriptor (random 256 bits: any two differ by about 128).
std::vector<Landmark> room(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> x(-1.5, 1.5), y(-1.0, 1.0), z(2.0, 4.0);
  std::vector<Landmark> out(static_cast<size_t>(n));
  for (auto& l : out) {
    l.position = Eigen::Vector3d(x(rng), y(rng), z(rng));
    l.descriptor = randomDescriptor(rng);
    l.hits_in_place = 10;
  }
  return out;
}

/// A camera at T_old_cur (old world frame) seeing the landmarks, plus `clutter` features
/// of their own and `walkers` copies of landmark descriptors 0.5 m from where the
/// landmarks are (what a walker or a look-alike corner offers).
gmc::features::FeatureSet frame(const std::vector<Landmark>& landmarks, const Isometry& T_old_cur, int clutter,
                                int walkers, std::mt19937& rng) {
  SeenFeatures seen(kCamera);
  const Isometry T_cur_old = T_old_cur.inverse();
  for (const auto& l : landmarks) seen.add(T_cur_old * l.position, l.descriptor);
  std::uniform_real_distribution<double> x(-1.0, 1.0), z(1.5, 4.0);
  for (int i = 0; i < clutter; ++i) seen.add(Eigen::Vector3d(x(rng), x(rng), z(rng)), randomDescriptor(rng));
  for (int i = 0; i < walkers && i < static_cast<int>(landmarks.size()); ++i)
    seen.add(T_cur_old * (landmarks[static_cast<size_t>(i)].position + Eigen::Vector3d(0.5, 0, 0)),
             landmarks[static_cast<size_t>(i)].descriptor);
  return seen.take();
}

Isometry pose(double yaw_deg, const Eigen::Vector3d& t) {
  Isometry T = Isometry::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = t;
  return T;
}

// The new map's frame is off the old one by a drift of 0.2 m and 12 degrees (what the
// prediction drifts over a lost second). Among walkers and clutter, the old landmarks
// give the correction back, but only once a second attempt, from another view, agrees.
TEST(MapRejoin, FindsTheOldFrameOnceTwoAttemptsAgree) {
  std::mt19937 rng(7);
  const auto landmarks = room(300, rng);
  MapRejoin rejoin(RejoinOptions{}, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
  ASSERT_TRUE(rejoin.freeze(0, landmarks, 10.0));
  ASSERT_TRUE(rejoin.active());
  const Isometry T_new_old = pose(12, {0.2, 0.0, -0.1});
  const gmc::features::Frontend frontend;
  RejoinAttempt first, second;
  const Isometry T_old_a = pose(3, {0.05, 0, 0.1}), T_old_b = pose(5, {0.08, 0.01, 0.12});
  const auto a =
      rejoin.attempt(frontend, frame(landmarks, T_old_a, 150, 60, rng), T_new_old * T_old_a, kCamera, &first);
  EXPECT_FALSE(a.has_value());
  EXPECT_GT(first.inliers, 100);
  const auto b =
      rejoin.attempt(frontend, frame(landmarks, T_old_b, 150, 60, rng), T_new_old * T_old_b, kCamera, &second);
  ASSERT_TRUE(b.has_value());
  EXPECT_TRUE(second.confirmed);
  EXPECT_EQ(b->map, 0);
  const Isometry error = b->T_map_current * T_new_old;  // identity when the correction is T_old_new
  EXPECT_LT(error.translation().norm(), 1e-3);
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), 1e-3);
  EXPECT_EQ(rejoin.release(0).size(), landmarks.size());
  EXPECT_FALSE(rejoin.active());
}

// Matches with no common correction (each frame offers the old descriptors at new random
// places, as a repeated texture would) never move the map.
TEST(MapRejoin, MatchesWithoutACommonCorrectionNeverRejoin) {
  std::mt19937 rng(3);
  const auto landmarks = room(300, rng);
  MapRejoin rejoin(RejoinOptions{}, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
  rejoin.freeze(0, landmarks, 0.0);
  const gmc::features::Frontend frontend;
  for (int k = 0; k < 10; ++k) {
    auto shuffled = landmarks;
    for (auto& l : shuffled) l.position = room(1, rng)[0].position;
    EXPECT_FALSE(
        rejoin.attempt(frontend, frame(shuffled, Isometry::Identity(), 100, 0, rng), Isometry::Identity(), kCamera)
            .has_value())
        << k;
  }
}

TEST(MapRejoin, EveryNthTrackedFrameAttemptsAndTheOldMapIsGivenUpInTime) {
  std::mt19937 rng(5);
  const auto landmarks = room(200, rng);
  RejoinOptions options;
  options.every_frames = 3;
  options.max_seconds = 2.0;
  MapRejoin rejoin(options, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
  rejoin.freeze(0, landmarks, 1.0);
  const gmc::features::Frontend frontend;
  const auto seen = frame(landmarks, Isometry::Identity(), 0, 0, rng);
  std::vector<int> matched;
  for (int k = 0; k < 6; ++k) {
    RejoinAttempt r;
    rejoin.attempt(frontend, seen, pose(20, {0.3, 0, 0}), kCamera, &r);
    matched.push_back(r.matches);
  }
  EXPECT_GT(matched[0], 100);
  EXPECT_EQ(matched[1], 0);
  EXPECT_EQ(matched[2], 0);
  EXPECT_GT(matched[3], 100);
  EXPECT_TRUE(rejoin.giveUpExpired(2.9).empty());
  EXPECT_TRUE(rejoin.active());
  EXPECT_EQ(rejoin.giveUpExpired(3.5), std::vector<int>{0});
  EXPECT_FALSE(rejoin.active());
}

// Maps left at successive re-anchors wait together, up to max_maps; when full, the oldest
// (the frame the trajectory started in) stays and the second oldest makes room. With
// max_maps = 1 a second map is not kept. Too few landmarks to ever agree are not kept.
TEST(MapRejoin, KeepsSeveralMapsTheOldestFirstAndNoneTooSmallToAgree) {
  std::mt19937 rng(9);
  const auto first = room(50, rng), second = room(80, rng), third = room(60, rng);
  RejoinOptions two;
  two.max_maps = 2;
  MapRejoin rejoin(two, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
  EXPECT_FALSE(rejoin.freeze(0, room(RejoinOptions{}.min_inliers - 1, rng), 0.0));
  EXPECT_FALSE(rejoin.active());
  EXPECT_TRUE(rejoin.freeze(1, first, 1.0));
  EXPECT_TRUE(rejoin.freeze(2, second, 2.0));
  EXPECT_TRUE(rejoin.freeze(3, third, 3.0));
  EXPECT_TRUE(rejoin.waiting(1));
  EXPECT_FALSE(rejoin.waiting(2));
  EXPECT_TRUE(rejoin.waiting(3));
  EXPECT_EQ(rejoin.release(3).size(), third.size());
  const auto kept = rejoin.release(1);
  ASSERT_EQ(kept.size(), first.size());
  EXPECT_FALSE(rejoin.active());
  RejoinOptions one;
  one.max_maps = 1;
  MapRejoin single(one, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
  EXPECT_TRUE(single.freeze(1, first, 1.0));
  EXPECT_FALSE(single.freeze(2, second, 2.0));
  EXPECT_EQ(single.release(1)[0].descriptor, first[0].descriptor);
  RejoinOptions off;
  off.enabled = false;
  MapRejoin disabled(off, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
  EXPECT_FALSE(disabled.freeze(1, first, 1.0));
  EXPECT_FALSE(disabled.active());
}

// Two maps wait, each in its own frame; attempts take them in turn, and the one the
// camera sees (the second, an intermediate map) is found with its own correction, not
// the first map's (whose landmarks are elsewhere).
TEST(MapRejoin, TriesTheWaitingMapsInTurnAndFindsTheOneInView) {
  std::mt19937 rng(11);
  const auto far_room = room(200, rng), near_room = room(200, rng);
  auto elsewhere = far_room;
  for (auto& l : elsewhere) l.position += Eigen::Vector3d(0, 0, 30);  // behind a wall, out of view
  MapRejoin rejoin(RejoinOptions{}, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
  ASSERT_TRUE(rejoin.freeze(0, elsewhere, 0.0));
  ASSERT_TRUE(rejoin.freeze(1, near_room, 1.0));
  const Isometry T_current_1 = pose(-8, {-0.15, 0.02, 0.05});  // map 1's frame -> the current map's
  const gmc::features::Frontend frontend;
  std::vector<int> tried;
  std::optional<gmc::vo::RejoinFound> found;
  for (int k = 0; k < 6 && !found; ++k) {
    const Isometry T_1_cur = pose(2 + k, {0.02 * k, 0, 0.1});
    RejoinAttempt r;
    found = rejoin.attempt(frontend, frame(near_room, T_1_cur, 100, 30, rng), T_current_1 * T_1_cur, kCamera, &r);
    tried.push_back(r.map);
  }
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(tried, (std::vector<int>{0, 1, 0, 1}));  // confirmed at map 1's second attempt
  EXPECT_EQ(found->map, 1);
  const Isometry error = found->T_map_current * T_current_1;
  EXPECT_LT(error.translation().norm(), 1e-3);
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), 1e-3);
  EXPECT_TRUE(rejoin.waiting(0));
  EXPECT_EQ(rejoin.waitingMaps(), (std::vector<int>{0, 1}));
  EXPECT_EQ(rejoin.release(1).size(), near_room.size());
  EXPECT_EQ(rejoin.waitingMaps(), std::vector<int>{0});
  // Restricted to one map, only that one is tried (and a map not waiting is none).
  RejoinAttempt r;
  rejoin.attempt(frontend, frame(near_room, Isometry::Identity(), 100, 30, rng), Isometry::Identity(), kCamera, &r, 0);
  EXPECT_EQ(r.map, 0);
  RejoinAttempt none;
  rejoin.attempt(frontend, frame(near_room, Isometry::Identity(), 100, 30, rng), Isometry::Identity(), kCamera, &none, 1);
  EXPECT_EQ(none.map, -1);
}

}  // namespace

namespace {

/// A map of `landmarks` (current world frame), every one with static evidence at
/// stamp 2, or every one seen moving (suspect until stamp 3).
gmc::vo::LandmarkMap currentMap(std::vector<Landmark> landmarks, bool seen_moving) {
  for (auto& l : landmarks) {
    l.evidence_since = 0;
    l.last_seen_in_place = 2.0;
    if (seen_moving) l.suspect_until = 3.0;
  }
  gmc::vo::LandmarkMap map;
  map.adopt(landmarks);
  return map;
}

}  // namespace

// A young map (walkers led it; what it froze is too little to agree) is kept for its
// first keyframe: that keyframe's features, matched against the current map's
// landmarks not seen moving, pose it in the current map and give the correction (its
// world <- the current one), once two attempts agree. Landmarks seen moving do not
// count; without young_map_anchor such a map is not kept at all.
TEST(MapRejoin, AYoungMapIsFoundByItsFirstKeyframeOnTheCurrentMapsRoom) {
  std::mt19937 rng(13);
  const auto old_room = room(300, rng);
  const Isometry T_new_old = pose(-10, {0.25, 0.0, 0.1});  // the re-anchor's guess, off
  auto new_room = old_room;
  for (auto& l : new_room) l.position = T_new_old * l.position;
  const Isometry T_old_anchor = pose(2, {0.03, 0, -0.05});
  gmc::vo::MapAnchor anchor{frame(old_room, T_old_anchor, 150, 60, rng), T_old_anchor};
  const auto walkers = room(5, rng);  // all the young map froze
  const gmc::features::Frontend frontend;
  // Today's frame sees nothing of what the young map froze.
  std::vector<Landmark> none;
  const auto today = frame(none, Isometry::Identity(), 200, 0, rng);

  MapRejoin rejoin(RejoinOptions{}, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
  ASSERT_TRUE(rejoin.freeze(0, walkers, 1.0, anchor));
  const auto moving_map = currentMap(new_room, true);
  RejoinAttempt untrusted;
  EXPECT_FALSE(rejoin.attempt(frontend, today, Isometry::Identity(), kCamera, &untrusted, -1, &moving_map, 2.0));
  EXPECT_FALSE(rejoin.attempt(frontend, today, Isometry::Identity(), kCamera, &untrusted, -1, &moving_map, 2.0));
  EXPECT_EQ(untrusted.matches, 0);

  const auto held_map = currentMap(new_room, false);
  RejoinAttempt first, second;
  EXPECT_FALSE(rejoin.attempt(frontend, today, Isometry::Identity(), kCamera, &first, -1, &held_map, 2.0));
  EXPECT_TRUE(first.by_anchor);
  EXPECT_GT(first.inliers, 100);
  const auto found = rejoin.attempt(frontend, today, Isometry::Identity(), kCamera, &second, -1, &held_map, 2.0);
  ASSERT_TRUE(found.has_value());
  EXPECT_TRUE(second.confirmed);
  EXPECT_EQ(found->map, 0);
  const Isometry error = found->T_map_current * T_new_old;  // identity when the correction is T_old_new
  EXPECT_LT(error.translation().norm(), 1e-3);
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), 1e-3);

  RejoinOptions off;
  off.young_map_anchor = false;
  MapRejoin without(off, gmc::vo::RefinementOptions{}, gmc::vo::InPlaceThreshold{});
  EXPECT_FALSE(without.freeze(0, walkers, 1.0, anchor));
  EXPECT_FALSE(without.active());
}
