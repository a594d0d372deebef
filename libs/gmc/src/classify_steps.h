#pragma once
// The steps of GmcClassifier::classify(), one function per section of the paper, and the
// buffers they share (kept between frames so steady state allocates nothing). Internal:
// not installed; tests include it to check each step on its own. doc/gmc.md explains
// every decision.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "gmc/gmc/gmc.h"

namespace gmc::detail {

constexpr int kBinnings = 4;   // base table, shifted in x, in z, in both (Alg. 1 l.13-15)
constexpr int kBinLimit = 60;  // patterns are clamped to [-kBinLimit, kBinLimit] per axis
constexpr int kBinSpan = 2 * kBinLimit + 1;

/// Half-interval offsets of the four tables, per axis (x, y, z).
constexpr std::array<std::array<float, 3>, kBinnings> kShift = {
    {{0.f, 0.f, 0.f}, {0.5f, 0.f, 0.f}, {0.f, 0.f, 0.5f}, {0.5f, 0.f, 0.5f}}};

/// round(v) clamped to [-kBinLimit, kBinLimit]; the shift to positive values makes the
/// truncating cast a floor (std::lround was a tenth of the run time).
inline int clampBin(float v) {
  const float c = std::clamp(v, static_cast<float>(-kBinLimit), static_cast<float>(kBinLimit));
  return static_cast<int>(c + (static_cast<float>(kBinLimit) + 0.5f)) - kBinLimit;
}

/// One integer per pattern (bx, by, bz), so a cell's votes are sorted and counted.
inline std::int32_t packCode(int bx, int by, int bz) {
  return ((bx + kBinLimit) * kBinSpan + (by + kBinLimit)) * kBinSpan + (bz + kBinLimit);
}
inline std::array<int, 3> unpackCode(std::int32_t code) {
  return {code / (kBinSpan * kBinSpan) - kBinLimit, (code / kBinSpan) % kBinSpan - kBinLimit,
          code % kBinSpan - kBinLimit};
}

using PatternCodes = std::array<std::int32_t, kBinnings>;  ///< a match's pattern in each table

/// Shifted tables (Alg. 1 l.13-15): the residual's pattern in each of the four tables.
inline PatternCodes patternCodes(const Eigen::Vector3f& e) {
  PatternCodes codes;
  for (int b = 0; b < kBinnings; ++b)
    codes[static_cast<size_t>(b)] = packCode(clampBin(e.x() - kShift[b][0]), clampBin(e.y() - kShift[b][1]),
                                             clampBin(e.z() - kShift[b][2]));
  return codes;
}

/// A match takes part only with finite, positive depths and a pixel inside the image.
inline bool isUsable(const MotionMatch& m, int image_width, int image_height) {
  return m.point_ref.allFinite() && m.point_cur.allFinite() && m.point_cur.z() > 0 && m.point_ref.z() > 0 &&
         m.pixel.allFinite() && m.pixel.x() >= 0 && m.pixel.y() >= 0 && m.pixel.x() < image_width &&
         m.pixel.y() < image_height;
}

/// Eq. (3) per axis of the reconstruction covariance, in pattern intervals.
struct ResidualNormaliser {
  explicit ResidualNormaliser(const GmcParams& p, const Isometry& T_ref_cur);
  Eigen::Vector3f operator()(const MotionMatch& m) const;

  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  double alpha, z_depth_power;
  bool squared;       ///< z_depth_power == 2, the default: avoids pow() per match
  float inv_int[3];   ///< 1 / interval per axis (0 for y unless use_y)
};

inline Eigen::Vector3f ResidualNormaliser::operator()(const MotionMatch& m) const {
  const Eigen::Vector3d r = m.point_ref - (R * m.point_cur + t);
  // The residual is split along the viewing ray (depth noise, ~d^2 on a Kinect) and
  // across it (keypoint noise, ~d), each normalised by the point's distance d to its own
  // power. Across-ray axes keep the camera's x (horizontal) and y (vertical) sense.
  const double d = m.point_cur.norm();
  const Eigen::Vector3d ray = m.point_cur / d;
  const Eigen::Vector3d across_x = Eigen::Vector3d::UnitY().cross(ray).normalized();
  const Eigen::Vector3d across_y = ray.cross(across_x);
  const double depth_scale = squared ? d * d : std::pow(d, z_depth_power);
  return Eigen::Vector3f(static_cast<float>(alpha * r.dot(across_x) / d) * inv_int[0],
                         static_cast<float>(alpha * r.dot(across_y) / d) * inv_int[1],
                         static_cast<float>(alpha * r.dot(ray) / depth_scale) * inv_int[2]);
}

/// Normalised residual and pattern codes per match; invalid matches keep valid = 0.
struct Residuals {
  std::vector<Eigen::Vector3f> e;
  std::vector<PatternCodes> code;
  std::vector<std::uint8_t> valid;
  int num_valid = 0;
};
void computeResiduals(const std::vector<MotionMatch>& matches, const Isometry& T_ref_cur, int image_width,
                      int image_height, const GmcParams& p, Residuals& out);

/// The grid actually used and the pixel -> cell mapping.
struct Grid {
  int cols = 0, rows = 0, image_width = 0, image_height = 0;
  int cells() const { return cols * rows; }
  int cellOf(const Eigen::Vector2f& px) const {
    const int cx = std::min(cols - 1, static_cast<int>(px.x() * cols / image_width));
    const int cy = std::min(rows - 1, static_cast<int>(px.y() * rows / image_height));
    return cy * cols + cx;
  }
};
/// The paper's grid, coarsened (aspect kept) while cells would hold fewer than
/// min_matches_per_cell matches on average.
Grid chooseGrid(const GmcParams& p, int num_valid, int image_width, int image_height);

/// Grid tensor (Alg. 1 l.4-8): valid matches counting-sorted by cell; the matches of cell
/// c are items[start[c] .. start[c+1]).
struct CellBuckets {
  std::vector<int> start, fill, items;
};
void bucketByCell(const std::vector<MotionMatch>& matches, const Residuals& res, const Grid& grid,
                  CellBuckets& out);

/// A leaf of the quadtree over one grid cell.
struct Leaf {
  int x0, y0, x1, y1, depth;
  int first, count;  // range in CellBuckets::items
  int binning = 0, winner = 0, winner_count = 0, second_count = 0;
  Eigen::Vector3f motion = Eigen::Vector3f::Zero();
  int cluster = -1;
  bool votes = false;
};

/// Pattern table (Alg. 1 l.9-11) for one leaf: winner and runner-up pattern in each of
/// the four tables; the leaf keeps the table whose winner holds most points (ties keep the
/// earlier, unshifted table).
void voteLeaf(Leaf& leaf, const std::vector<PatternCodes>& codes, const std::vector<int>& items,
              std::vector<std::int32_t>& sort_buf);

struct QuadtreeBuffers {
  std::vector<int> scratch, stack;
  std::vector<std::int32_t> sort_buf;
};
/// Quadtree split (Sec. 3.3): every grid cell is a root; a leaf splits into four while
/// its winner holds < p_min * n_i and n_i > n_min, down to max_depth. Reorders
/// buckets.items so that each leaf's matches are contiguous.
void splitQuadtree(const std::vector<MotionMatch>& matches, const Residuals& res, const Grid& grid,
                   const GmcParams& p, CellBuckets& buckets, std::vector<Leaf>& leaves, QuadtreeBuffers& buf);

/// Leaf motion: mean residual of the members of its winning pattern; leaves with at least
/// min_cell_points matches vote in the merge.
void leafMotions(const Residuals& res, const std::vector<int>& items, int min_cell_points,
                 std::vector<Leaf>& leaves);
inline bool inWinner(const Leaf& leaf, const Residuals& res, int i) {
  return res.code[static_cast<size_t>(i)][static_cast<size_t>(leaf.binning)] == leaf.winner;
}

/// 8-neighbourhood of leaves, found on a raster at the finest quadtree resolution; flat
/// (CSR): neighbours of leaf a are nb[nb_start[a] .. nb_start[a+1]).
struct Adjacency {
  std::vector<int> raster;
  std::vector<std::array<int, 2>> edges;
  std::vector<int> nb_start, nb_fill, nb, nb_stamp;
  struct Range {
    const int *b, *e;
    const int* begin() const { return b; }
    const int* end() const { return e; }
  };
  Range neighbours(size_t id) const { return {nb.data() + nb_start[id], nb.data() + nb_start[id + 1]}; }
};
void buildAdjacency(const std::vector<Leaf>& leaves, const Grid& grid, int max_depth, Adjacency& adj);

/// A cluster while it grows.
struct ClusterAcc {
  Eigen::Vector3f weighted = Eigen::Vector3f::Zero();
  int support = 0;
  int leaves = 0;
  Eigen::Vector3f mean() const { return weighted / static_cast<float>(support); }
};
/// Per-axis (Chebyshev) agreement of two motions, in intervals.
inline bool compatible(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float tol) {
  return std::abs(a.x() - b.x()) <= tol && std::abs(a.y() - b.y()) <= tol && std::abs(a.z() - b.z()) <= tol;
}
inline float chebyshev(const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return (a - b).cwiseAbs().maxCoeff(); }

struct MergeBuffers {
  std::vector<int> order, queue;
  std::vector<ClusterAcc> acc;
};
/// Alg. 2, merge with non-maximum suppression: voting leaves in decreasing support seed
/// clusters; a seed absorbs adjacent voting leaves within merge_tolerance of the
/// cluster's running mean. Leaves out of the merge keep cluster -1.
void mergeWithNms(std::vector<Leaf>& leaves, const Adjacency& adj, float merge_tolerance, MergeBuffers& buf);
/// "Until the assignment stops changing": leaves re-join the compatible adjacent cluster
/// with most support. Returns the rounds run.
int reassignUntilStable(std::vector<Leaf>& leaves, const Adjacency& adj, float merge_tolerance, int max_rounds,
                        MergeBuffers& buf);

/// Clusters of at least min_cluster_size into result.clusters (remap: old -> new index,
/// -1 = dropped), then the background: the cluster near zero motion with most support,
/// or, when none is near zero, the largest (static_fallback).
void chooseBackground(const std::vector<ClusterAcc>& acc, const GmcParams& p, std::vector<int>& remap,
                      GmcResult& result);

struct LabelBuffers {
  std::vector<Eigen::Vector3d> motion_sum;
  std::vector<int> motion_count;
  std::vector<Eigen::Vector3f> static_cands, dynamic_cands;
};
/// Per-match labels: each match takes the nearest of the leaf's candidate motions
/// (background, own cluster, adjacent clusters); also the clusters' mean 3-D residuals.
void labelMatches(const std::vector<MotionMatch>& matches, const Isometry& T_ref_cur, const Residuals& res,
                  const std::vector<int>& items, const std::vector<Leaf>& leaves, const Adjacency& adj,
                  LabelBuffers& buf, GmcResult& result);

/// Leaves as public cells; label counters.
void writeCells(const std::vector<Leaf>& leaves, GmcResult& result);
void countLabels(GmcResult& result);

/// Every buffer of one classifier.
struct ClassifyWorkspace {
  Residuals residuals;
  CellBuckets buckets;
  std::vector<Leaf> leaves;
  QuadtreeBuffers quadtree;
  Adjacency adjacency;
  MergeBuffers merge;
  std::vector<int> remap;
  LabelBuffers labels;
};

}  // namespace gmc::detail
