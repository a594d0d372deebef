// The steps of classify() on their own, where the paper defines their result
// (libs/gmc/src/classify_steps.h; doc/gmc.md).
#include <gtest/gtest.h>

#include "classify_steps.h"

namespace {

using namespace gmc;
using namespace gmc::detail;

MotionMatch match(float u, float v, const Eigen::Vector3d& ref, const Eigen::Vector3d& cur) {
  return {Eigen::Vector2f(u, v), ref, cur};
}

// Eq. (3): lateral residual over distance, depth residual over distance squared, in intervals.
TEST(GmcSteps, ResidualIsNormalisedByDistanceAcrossAndDistanceSquaredAlongTheRay) {
  GmcParams p;  // alpha 100, intervals 1, z power 2
  const ResidualNormaliser normalise(p, Isometry::Identity());
  const auto e = normalise(match(320, 240, {0.01, 0.0, 2.02}, {0, 0, 2}));
  EXPECT_NEAR(e.x(), 100 * 0.01 / 2, 1e-6);
  EXPECT_NEAR(e.z(), 100 * 0.02 / 4, 1e-6);
  EXPECT_EQ(e.y(), 0.f);  // use_y off: the vertical axis does not vote
  p.e_int_x = 0.5;
  EXPECT_NEAR(ResidualNormaliser(p, Isometry::Identity())(match(0, 0, {0.01, 0, 2}, {0, 0, 2})).x(), 1.0, 1e-6);
  // A static point seen through the right motion has no residual.
  Isometry T = Isometry::Identity();
  T.translation() = Eigen::Vector3d(0.1, 0, 0.05);
  const Eigen::Vector3d cur(0.5, -0.2, 3.0);
  EXPECT_LT(ResidualNormaliser(p, T)(match(0, 0, T * cur, cur)).norm(), 1e-5);
}

TEST(GmcSteps, UnusableMatchesAreThoseWithoutDepthOrOutsideTheImage) {
  EXPECT_TRUE(isUsable(match(10, 10, {0, 0, 1}, {0, 0, 1}), 640, 480));
  EXPECT_FALSE(isUsable(match(10, 10, {0, 0, 1}, {0, 0, 0}), 640, 480));
  EXPECT_FALSE(isUsable(match(10, 10, {0, 0, std::nan("")}, {0, 0, 1}), 640, 480));
  EXPECT_FALSE(isUsable(match(640, 10, {0, 0, 1}, {0, 0, 1}), 640, 480));
}

// Alg. 1 l.13-15: a motion on a bin border of the base table is mid-bin in the x-shifted one.
TEST(GmcSteps, ShiftedTablesPutABinBorderInTheMiddleOfABin) {
  const auto codes = patternCodes(Eigen::Vector3f(1.5f, 0.f, -0.2f));
  EXPECT_EQ(unpackCode(codes[0]), (std::array<int, 3>{2, 0, 0}));   // 1.5 rounds up
  EXPECT_EQ(unpackCode(codes[1]), (std::array<int, 3>{1, 0, 0}));   // 1.0 in the x-shifted table
  EXPECT_EQ(unpackCode(codes[2]), (std::array<int, 3>{2, 0, -1}));  // -0.7 in the z-shifted table
  EXPECT_EQ(unpackCode(codes[3]), (std::array<int, 3>{1, 0, -1}));
  EXPECT_EQ(unpackCode(patternCodes(Eigen::Vector3f(500.f, 0, 0))[0])[0], kBinLimit);  // clamped
}

TEST(GmcSteps, GridIsThePapersUnlessCellsWouldBeTooSparse) {
  GmcParams p;  // 20 x 15, at least 4 matches per cell
  const Grid dense = chooseGrid(p, 1500, 640, 480);
  EXPECT_EQ(dense.cols, 20);
  EXPECT_EQ(dense.rows, 15);
  const Grid sparse = chooseGrid(p, 300, 640, 480);  // 1 per cell: sides halved
  EXPECT_EQ(sparse.cols, 10);
  EXPECT_EQ(sparse.rows, 8);
  EXPECT_EQ(sparse.cellOf(Eigen::Vector2f(639.9f, 479.9f)), 10 * 8 - 1);
  p.min_matches_per_cell = 0;
  EXPECT_EQ(chooseGrid(p, 10, 640, 480).cols, 20);
}

Residuals residualsOf(const std::vector<Eigen::Vector3f>& e) {
  Residuals r;
  r.e = e;
  for (const auto& v : e) r.code.push_back(patternCodes(v)), r.valid.push_back(1);
  r.num_valid = static_cast<int>(e.size());
  return r;
}

// Alg. 1 l.9-11: the winner and the runner-up of the leaf's pattern table.
TEST(GmcSteps, LeafVoteKeepsTheWinningPatternAndTheRunnerUp) {
  const auto res = residualsOf({{0.1f, 0, 0}, {-0.2f, 0, 0.1f}, {0.3f, 0, 0}, {3.1f, 0, 0}, {2.9f, 0, 0}});
  std::vector<int> items = {0, 1, 2, 3, 4};
  Leaf leaf{};
  leaf.first = 0;
  leaf.count = 5;
  std::vector<std::int32_t> buf;
  voteLeaf(leaf, res.code, items, buf);
  EXPECT_EQ(leaf.winner_count, 3);
  EXPECT_EQ(leaf.second_count, 2);
  EXPECT_EQ(leaf.binning, 0);  // the z-shifted table also has 3 in its winner: ties keep the base table
  EXPECT_EQ(unpackCode(leaf.winner), (std::array<int, 3>{0, 0, 0}));
}

/// n matches spread over the pixel rectangle, with residual e.
void addMatches(std::vector<MotionMatch>& m, std::vector<Eigen::Vector3f>& e, float u0, float u1, float v0,
                float v1, int n, const Eigen::Vector3f& residual) {
  for (int k = 0; k < n; ++k) {
    const float u = u0 + (u1 - u0) * (k % 5 + 0.5f) / 5, v = v0 + (v1 - v0) * (k / 5 % 5 + 0.5f) / 5;
    m.push_back(match(u, v, {0, 0, 2}, {0, 0, 2}));
    e.push_back(residual);
  }
}

// Sec. 3.3: a cell whose winner holds less than p_min of its points splits into four.
TEST(GmcSteps, QuadtreeSplitsAMixedCellAndKeepsAUniformOne) {
  std::vector<MotionMatch> m;
  std::vector<Eigen::Vector3f> e;
  addMatches(m, e, 0, 16, 0, 32, 10, {0, 0, 0});   // cell 0, left half static
  addMatches(m, e, 16, 32, 0, 32, 10, {3, 0, 0});  // cell 0, right half moving
  addMatches(m, e, 32, 64, 0, 32, 20, {0, 0, 0});  // cell 1 uniform
  const auto res = residualsOf(e);
  GmcParams p;
  p.min_matches_per_cell = 0;
  p.grid_cols = 2;
  p.grid_rows = 1;
  const Grid grid = chooseGrid(p, res.num_valid, 64, 32);
  CellBuckets buckets;
  bucketByCell(m, res, grid, buckets);
  std::vector<Leaf> leaves;
  QuadtreeBuffers buf;
  splitQuadtree(m, res, grid, p, buckets, leaves, buf);
  ASSERT_EQ(leaves.size(), 5u);  // cell 0 split once into four, cell 1 kept
  int leaves_of_cell0 = 0;
  for (const auto& leaf : leaves) {
    if (leaf.x0 >= 32) {
      EXPECT_EQ(leaf.depth, 0);
      EXPECT_EQ(leaf.winner_count, 20);
      continue;
    }
    ++leaves_of_cell0;
    EXPECT_EQ(leaf.depth, 1);
    EXPECT_EQ(leaf.winner_count, leaf.count) << "each quadrant holds one motion";
  }
  EXPECT_EQ(leaves_of_cell0, 4);
}

Leaf leafAt(int x0, int y0, int size, int support, const Eigen::Vector3f& motion) {
  Leaf l{};
  l.x0 = x0, l.y0 = y0, l.x1 = x0 + size, l.y1 = y0 + size;
  l.count = l.winner_count = support;
  l.motion = motion;
  l.votes = true;
  return l;
}

// Alg. 2: adjacent leaves of one motion merge; the strongest leaf seeds first.
TEST(GmcSteps, MergeJoinsAdjacentLeavesOfOneMotionAndSeparatesOthers) {
  // 3 x 1 grid of 10 px cells: static, static, moving.
  std::vector<Leaf> leaves = {leafAt(0, 0, 10, 5, {0, 0, 0}), leafAt(10, 0, 10, 8, {0.3f, 0, 0}),
                              leafAt(20, 0, 10, 6, {3, 0, 0})};
  const Grid grid{3, 1, 30, 10};
  Adjacency adj;
  buildAdjacency(leaves, grid, 0, adj);
  EXPECT_EQ(std::vector<int>(adj.neighbours(1).begin(), adj.neighbours(1).end()).size(), 2u);
  EXPECT_EQ(std::vector<int>(adj.neighbours(0).begin(), adj.neighbours(0).end()), std::vector<int>{1});
  MergeBuffers buf;
  mergeWithNms(leaves, adj, 0.75f, buf);
  EXPECT_EQ(buf.order, (std::vector<int>{1, 2, 0}));  // decreasing support
  EXPECT_EQ(leaves[0].cluster, leaves[1].cluster);
  EXPECT_NE(leaves[2].cluster, leaves[1].cluster);
  ASSERT_EQ(buf.acc.size(), 2u);
  EXPECT_EQ(buf.acc[0].support, 13);
  EXPECT_NEAR(buf.acc[0].mean().x(), 0.3 * 8 / 13, 1e-6);  // support-weighted mean
  EXPECT_EQ(reassignUntilStable(leaves, adj, 0.75f, 4, buf), 1);  // already stable
}

ClusterAcc acc(float mx, int support) {
  ClusterAcc a;
  a.weighted = Eigen::Vector3f(mx, 0, 0) * static_cast<float>(support);
  a.support = support;
  a.leaves = 1;
  return a;
}

// Sec. 3.3 prior: the background is the cluster near zero motion with most support;
// without one, the largest cluster (the guess is off).
TEST(GmcSteps, BackgroundIsTheLargestClusterNearZeroOrElseTheLargest) {
  GmcParams p;  // min_cluster_size 10, static_tolerance 1
  std::vector<int> remap;
  GmcResult r;
  chooseBackground({acc(0.2f, 40), acc(5, 60), acc(-0.5f, 50), acc(0, 4)}, p, remap, r);
  EXPECT_EQ(remap, (std::vector<int>{0, 1, 2, -1}));  // the 4-point cluster is dropped
  EXPECT_EQ(r.static_cluster, 2);
  EXPECT_FALSE(r.static_fallback);
  EXPECT_TRUE(r.clusters[0].is_static);
  EXPECT_FALSE(r.clusters[1].is_static);
  GmcResult off;
  chooseBackground({acc(3, 40), acc(6, 60), acc(6.5f, 20)}, p, remap, off);
  EXPECT_TRUE(off.static_fallback);
  EXPECT_EQ(off.static_cluster, 1);
  EXPECT_FALSE(off.clusters[0].is_static);
  EXPECT_TRUE(off.clusters[2].is_static);  // within the tolerance of the background
}

}  // namespace
