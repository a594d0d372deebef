#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gmc/mapping/map_quality.h"
#include "gmc/mapping/static_map.h"
#include "mapping_fixtures.h"

namespace {

using namespace gmc::mapping;
using namespace gmc::mapping::testing;
const gmc::Isometry kIdentity = gmc::Isometry::Identity();

/// Ground truth of three frames from one pose: a person at 0.55 m before the wall
/// (4 voxels), the empty wall (100 voxels), and a person leaning on the wall (its 4
/// voxels are wall voxels too, so not people-only).
GroundTruthVoxels threeFrameTruth() {
  GroundTruthVoxels truth(kVoxel, 2.0, 1);
  truth.addFrame(patchWithPerson(), personMask(), kIdentity);
  truth.addFrame(patchFrame(), cv::Mat::zeros(10, 10, CV_8UC1), kIdentity);
  truth.addFrame(patchWithPerson(kWallRaw), personMask(), kIdentity);
  truth.addFrame(patchFrame(15250), cv::Mat::zeros(10, 10, CV_8UC1), kIdentity);  // 3.05 m: beyond range
  return truth;
}

TEST(MapQuality, CountsGhostsAndCoverageOfAHandBuiltMap) {
  const GroundTruthVoxels truth = threeFrameTruth();
  EXPECT_EQ(truth.staticKeys().size(), 100u);
  EXPECT_EQ(truth.dynamicKeys().size(), 8u);

  octomap::OcTree map(kVoxel);
  map.updateNode(-0.05, -0.05, 0.55, true);  // two of the four people-only voxels occupied
  map.updateNode(0.05, 0.05, 0.55, true);
  map.updateNode(0.05, -0.05, 0.55, false);  // one known free
  for (int i = 0; i < 5; ++i)                // half the wall: x < 0
    for (int j = 0; j < 10; ++j) map.updateNode(-0.45 + 0.1 * i, -0.45 + 0.1 * j, 1.05, true);
  map.updateNode(0.05, 0.05, 2.05, true);    // occupied but in no ground-truth set

  const MapQuality q = evaluate(map, truth);
  EXPECT_EQ(q.dynamic_only_voxels, 4u);
  EXPECT_EQ(q.ghost_voxels, 2u);
  EXPECT_EQ(q.static_voxels_seen, 100u);
  EXPECT_EQ(q.static_voxels_occupied, 50u);
  EXPECT_DOUBLE_EQ(q.static_coverage(), 0.5);
  EXPECT_EQ(truth.evaluate(map).ghost_voxels, q.ghost_voxels);
}

TEST(MapQuality, MaskedBuilderHasNoGhostsAndMissesOnlyTheHiddenWall) {
  const GroundTruthVoxels truth = threeFrameTruth();
  StaticMapOptions o;
  o.resolution = kVoxel;
  o.pixel_step = 1;
  o.min_range = 0.1;
  o.mask_dilate_px = 0;  // the exact mask: pixel counts stay simple
  StaticMapBuilder with_mask(o), without_mask(o);
  for (int i = 0; i < 3; ++i) {
    with_mask.insertFrame(patchWithPerson(), personMask(), kIdentity);
    without_mask.insertFrame(patchWithPerson(), cv::Mat(), kIdentity);
  }
  const MapQuality good = evaluate(with_mask.tree(), truth), bad = evaluate(without_mask.tree(), truth);
  EXPECT_EQ(bad.ghost_voxels, 4u);  // every people-only voxel is a ghost
  EXPECT_EQ(good.ghost_voxels, 0u);
  // The 4 wall voxels behind the person are never seen by these frames.
  EXPECT_EQ(bad.static_voxels_occupied, 96u);
  EXPECT_EQ(good.static_voxels_occupied, 96u);
  EXPECT_DOUBLE_EQ(good.static_coverage(), 0.96);
}

TEST(MapQuality, FollowsTheMapsDepthRange) {
  StaticMapOptions o;
  o.resolution = kVoxel;
  o.pixel_step = 1;
  o.min_range = 0.7;  // the person at 0.55 m is closer: neither mapped nor counted
  GroundTruthVoxels truth(o);
  truth.addFrame(patchWithPerson(), personMask(), kIdentity);
  EXPECT_EQ(truth.dynamicKeys().size(), 0u);
  EXPECT_EQ(truth.staticKeys().size(), 96u);
  EXPECT_DOUBLE_EQ(truth.resolution(), kVoxel);
}

TEST(MapQuality, RejectsMismatchedInputs) {
  const GroundTruthVoxels truth = threeFrameTruth();
  octomap::OcTree other(0.05);
  EXPECT_THROW(evaluate(other, truth), std::invalid_argument);
  GroundTruthVoxels t(kVoxel, 2.0, 1);
  EXPECT_THROW(t.addFrame(patchFrame(), cv::Mat(), kIdentity), std::invalid_argument);
}

TEST(MapQuality, JsonNamesEveryField) {
  MapQuality q;
  q.ghost_voxels = 3, q.dynamic_only_voxels = 7, q.static_voxels_seen = 10, q.static_voxels_occupied = 4;
  const auto json = nlohmann::json::parse(toJson(q));
  EXPECT_EQ(json.at("ghost_voxels"), 3);
  EXPECT_EQ(json.at("dynamic_only_voxels"), 7);
  EXPECT_EQ(json.at("static_voxels_seen"), 10);
  EXPECT_EQ(json.at("static_voxels_occupied"), 4);
  EXPECT_DOUBLE_EQ(json.at("static_coverage").get<double>(), 0.4);
}

}  // namespace
