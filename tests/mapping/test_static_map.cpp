#include <gtest/gtest.h>

#include <filesystem>

#include "gmc/mapping/map_quality.h"
#include "gmc/mapping/static_map.h"

namespace {

using namespace gmc::mapping;

/// A camera at the origin looking along +z at a wall 2 m away; optionally a "person"
/// (a box of pixels at 1 m) in the middle, marked in the mask.
gmc::datasets::RgbdFrame wall(bool person, cv::Mat* mask) {
  gmc::datasets::RgbdFrame f;
  f.camera.fx = f.camera.fy = 100, f.camera.cx = 80, f.camera.cy = 60;
  f.camera.width = 160, f.camera.height = 120;
  f.rgb = cv::Mat(120, 160, CV_8UC3, cv::Scalar(0, 0, 0));
  f.depth = cv::Mat(120, 160, CV_16UC1, cv::Scalar(10000));
  *mask = cv::Mat::zeros(120, 160, CV_8UC1);
  if (person) {
    f.depth(cv::Rect(60, 40, 40, 40)).setTo(5000);
    (*mask)(cv::Rect(60, 40, 40, 40)).setTo(255);
  }
  return f;
}

bool occupiedAt(const octomap::OcTree& t, double x, double y, double z) {
  const auto* n = t.search(x, y, z);
  return n && t.isNodeOccupied(n);
}

TEST(StaticMap, WallIsOccupiedAndSpaceBeforeItFree) {
  StaticMapOptions o;
  o.pixel_step = 2;
  StaticMapBuilder b(o);
  cv::Mat mask;
  const auto f = wall(false, &mask);
  for (int i = 0; i < 3; ++i) b.insertFrame(f, mask, gmc::Isometry::Identity());
  EXPECT_TRUE(occupiedAt(b.tree(), 0.0, 0.0, 2.0));
  EXPECT_FALSE(occupiedAt(b.tree(), 0.0, 0.0, 1.0));
  const auto* free_node = b.tree().search(0.0, 0.0, 1.0);
  ASSERT_NE(free_node, nullptr);  // known free, not unknown
  EXPECT_GT(b.stats().occupied_leaves, 50u);
}

TEST(StaticMap, MaskedPeopleLeaveNoVoxelAndClearEarlierOnes) {
  StaticMapOptions o;
  o.pixel_step = 2;
  StaticMapBuilder b(o);
  cv::Mat mask;
  // Unmasked first: the person ends up in the map (what happens without GMC).
  const auto f = wall(true, &mask);
  b.insertFrame(f, cv::Mat(), gmc::Isometry::Identity());
  EXPECT_TRUE(occupiedAt(b.tree(), 0.0, 0.0, 1.0));
  // Masked frames while the person stands there: rays to the person clear the space in
  // front of them; the wall beside them is mapped.
  StaticMapBuilder fresh(o);
  for (int i = 0; i < 5; ++i) fresh.insertFrame(f, mask, gmc::Isometry::Identity());
  EXPECT_FALSE(occupiedAt(fresh.tree(), 0.0, 0.0, 1.0));
  const auto* before = fresh.tree().search(0.0, 0.0, 0.5);
  ASSERT_NE(before, nullptr);
  EXPECT_FALSE(fresh.tree().isNodeOccupied(before));
  EXPECT_TRUE(occupiedAt(fresh.tree(), 0.6, 0.0, 2.0));
  // Once the person has left, rays to the wall clear the voxel the unmasked frame left.
  cv::Mat empty_mask;
  const auto gone = wall(false, &empty_mask);
  for (int i = 0; i < 10; ++i) b.insertFrame(gone, empty_mask, gmc::Isometry::Identity());
  EXPECT_FALSE(occupiedAt(b.tree(), 0.0, 0.0, 1.0));
}

TEST(StaticMap, WrittenMapReloads) {
  StaticMapBuilder b;
  cv::Mat mask;
  b.insertFrame(wall(false, &mask), mask, gmc::Isometry::Identity());
  const auto path = (std::filesystem::temp_directory_path() / "gmc_test_map.bt").string();
  b.writeBinary(path);
  octomap::OcTree back(path);
  EXPECT_EQ(back.getNumLeafNodes(), b.tree().getNumLeafNodes());
  std::filesystem::remove(path);
  EXPECT_THROW(b.writeBinary("/nonexistent/dir/map.bt"), std::runtime_error);
}

TEST(MapQuality, GhostVoxelsAndCoverage) {
  StaticMapOptions o;
  o.pixel_step = 2;
  cv::Mat mask;
  const auto f = wall(true, &mask);
  GroundTruthVoxels truth(o.resolution, o.max_range, o.pixel_step);
  truth.addFrame(f, mask, gmc::Isometry::Identity());

  StaticMapBuilder with_mask(o), without_mask(o);
  for (int i = 0; i < 3; ++i) {
    with_mask.insertFrame(f, mask, gmc::Isometry::Identity());
    without_mask.insertFrame(f, cv::Mat(), gmc::Isometry::Identity());
  }
  const auto good = truth.evaluate(with_mask.tree()), bad = truth.evaluate(without_mask.tree());
  EXPECT_GT(bad.dynamic_only_voxels, 10u);
  EXPECT_EQ(bad.ghost_voxels, bad.dynamic_only_voxels);  // every person voxel is a ghost
  EXPECT_EQ(good.ghost_voxels, 0u);
  EXPECT_GT(good.static_coverage(), 0.95);
}

}  // namespace
