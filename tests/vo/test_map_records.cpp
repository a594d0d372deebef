#include <gtest/gtest.h>

#include <map>

#include "gmc/vo/map_records.h"

namespace {

using gmc::Isometry;
using gmc::vo::MapRecords;
using gmc::vo::RevisedPose;

/// The true camera at frame n: 1 cm and 0.2 deg per frame (constant velocity, so a bridge
/// of lost frames between two true poses is exact).
Isometry truth(long n) {
  Isometry T = Isometry::Identity();
  T.linear() = Eigen::AngleAxisd(0.2 * M_PI / 180.0 * static_cast<double>(n), Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.01 * static_cast<double>(n), 0, 0.002 * static_cast<double>(n));
  return T;
}

Isometry offset(double yaw_deg, const Eigen::Vector3d& t) {
  Isometry T = Isometry::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

RevisedPose given(long n, const Isometry& T_root_map) { return {n, 0.1 * static_cast<double>(n), T_root_map.inverse() * truth(n)}; }

std::vector<std::pair<long, double>> lostFrames(long first, long last) {
  std::vector<std::pair<long, double>> out;
  for (long n = first; n <= last; ++n) out.push_back({n, 0.1 * static_cast<double>(n)});
  return out;
}

/// Three maps: 0 (frames 1-10), lost 11-15, map 1 re-anchored 6 deg and 0.2 m off
/// (16-30), lost 31-35, map 2 another 0.3 m off (36-45). Poses given out in each map's
/// own frame; T_root[k] takes map k's frame into map 0's.
struct ThreeMaps {
  MapRecords records;
  std::vector<Isometry> T_root{Isometry::Identity(), offset(6, {0.2, 0, 0}), offset(-4, {0.1, 0.3, 0})};
  ThreeMaps() {
    records.reanchor(0, given(10, T_root[0]), 1, lostFrames(11, 15));
    for (long n = 16; n <= 30; ++n) records.add(given(n, T_root[1]));
    for (long n = 31; n <= 35; ++n) records.add(given(n, T_root[1]));  // lost on map 1: its guesses
    records.reanchor(1, given(30, T_root[1]), 2, lostFrames(31, 35));
    for (long n = 36; n <= 45; ++n) records.add(given(n, T_root[2]));
  }
  /// T_a_b between the frames of two maps.
  Isometry between(int a, int b) const { return T_root[static_cast<size_t>(a)].inverse() * T_root[static_cast<size_t>(b)]; }
};

/// Frame number -> last revision (later ones supersede earlier ones, as the app writes them).
std::map<long, Isometry> lastRevisions(const std::vector<RevisedPose>& revised) {
  std::map<long, Isometry> out;
  for (const auto& r : revised) out[r.frame_number] = r.T_world_camera;
  return out;
}

double positionError(const Isometry& a, const Isometry& b) { return (a.translation() - b.translation()).norm(); }

// The current map finds the intermediate one first, then both find the first map: every
// frame of maps 1 and 2 and both lost stretches end where the camera was, in map 0's frame.
TEST(MapRecords, AChainOfJoinsRevisesEveryMapIntoTheFirstFrame) {
  ThreeMaps m;
  std::vector<RevisedPose> revised;
  EXPECT_EQ(m.records.join(1, 2, m.between(1, 2), revised), 1);
  EXPECT_EQ(m.records.frameOf(2), 1);
  // In map 1's frame now: map 2's frames and the lost frames 31-35 between them.
  auto after_first = lastRevisions(revised);
  EXPECT_EQ(after_first.size(), 15u);
  for (const auto& [n, T] : after_first) EXPECT_LT(positionError(T, m.T_root[1].inverse() * truth(n)), 1e-9) << n;
  revised.clear();
  EXPECT_EQ(m.records.join(0, 2, m.between(0, 1), revised), 0);
  const auto last = lastRevisions(revised);
  EXPECT_EQ(last.size(), 35u);  // 11-45: lost, map 1, lost, map 2
  for (long n = 11; n <= 45; ++n) {
    ASSERT_TRUE(last.count(n)) << n;
    EXPECT_LT(positionError(last.at(n), truth(n)), 1e-9) << n;
  }
  EXPECT_EQ(m.records.currentFrame(), 0);
}

// The current map finds the first map directly; the intermediate map, found later, is the
// one that moves (the first map's frame stays), and both lost stretches are bridged then.
TEST(MapRecords, AMapFoundAfterTheFirstOneMovesIntoItsFrame) {
  ThreeMaps m;
  std::vector<RevisedPose> revised;
  EXPECT_EQ(m.records.join(0, 2, m.between(0, 2), revised), 0);
  auto first = lastRevisions(revised);
  EXPECT_EQ(first.size(), 10u);  // map 2 only: the lost frames before it left map 1
  for (const auto& [n, T] : first) EXPECT_LT(positionError(T, truth(n)), 1e-9) << n;
  revised.clear();
  // The current map (in map 0's frame now) finds map 1: T_1_current = T_1_0.
  EXPECT_EQ(m.records.join(1, 2, m.between(1, 0), revised), 0);
  const auto second = lastRevisions(revised);
  EXPECT_EQ(second.size(), 25u);  // 11-15 bridged, map 1's 16-30, 31-35 bridged
  for (const auto& [n, T] : second) EXPECT_LT(positionError(T, truth(n)), 1e-9) << n;
  EXPECT_FALSE(second.count(40));
}

// A map given up is forgotten: its frames stay as given out, and the lost frames that
// led away from it are never bridged. Revising a frame of the current map is kept.
TEST(MapRecords, AForgottenMapIsNeverRevisedAndRevisionsOfTheCurrentMapAreKept) {
  ThreeMaps m;
  m.records.forget(1);
  const RevisedPose better{40, 4.0, m.T_root[2].inverse() * truth(40) * offset(0, {0.0, 0.0, 0.01})};
  m.records.revise(better);
  std::vector<RevisedPose> revised;
  m.records.join(0, 2, m.between(0, 2), revised);
  const auto last = lastRevisions(revised);
  EXPECT_EQ(last.size(), 10u);
  EXPECT_FALSE(last.count(20));
  EXPECT_FALSE(last.count(33));
  EXPECT_NEAR(positionError(last.at(40), truth(40)), 0.01, 1e-9);
  m.records.clear();
  EXPECT_TRUE(m.records.empty());
}

}  // namespace
