// GMC: grid-based motion clustering. The numbered steps follow Algorithm 1 (assignment)
// and Algorithm 2 (merge) of the paper; doc/gmc.md explains each decision.
#include "gmc/gmc/gmc.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace gmc {
namespace {

constexpr int kBinnings = 4;       // base table, shifted in x, in z, in both (Alg. 1 l.13-15)
constexpr int kBinLimit = 60;      // patterns are clamped to [-kBinLimit, kBinLimit] per axis
constexpr int kBinSpan = 2 * kBinLimit + 1;

/// Half-interval offsets of the four tables, per axis (x, y, z).
constexpr std::array<std::array<float, 3>, kBinnings> kShift = {{
    {0.f, 0.f, 0.f}, {0.5f, 0.f, 0.f}, {0.f, 0.f, 0.5f}, {0.5f, 0.f, 0.5f}}};

/// round(v) clamped to [-kBinLimit, kBinLimit]; the shift to positive values makes the
/// truncating cast a floor (std::lround was a tenth of the run time).
inline int clampBin(float v) {
  const float c = std::clamp(v, static_cast<float>(-kBinLimit), static_cast<float>(kBinLimit));
  return static_cast<int>(c + (static_cast<float>(kBinLimit) + 0.5f)) - kBinLimit;
}

}  // namespace

struct GmcClassifier::Workspace {
  struct Leaf {
    int x0, y0, x1, y1, depth;
    int first, count;          // range in `items`
    int binning = 0, winner = 0, winner_count = 0, second_count = 0;
    Eigen::Vector3f motion = Eigen::Vector3f::Zero();
    int cluster = -1;
    bool votes = false;
  };

  std::vector<Eigen::Vector3f> e;           // normalised residual per match (scaled by 1/e_int)
  std::vector<std::array<std::int32_t, kBinnings>> code;  // pattern code per match and table
  std::vector<std::uint8_t> valid;
  std::vector<int> cell_start, cell_fill, items, scratch;
  std::vector<Leaf> leaves;
  std::vector<std::int32_t> sort_buf;
  std::vector<int> raster;                  // leaf id per finest quadtree unit
  std::vector<int> order, queue;
  // Leaf adjacency, flat (CSR): neighbours of leaf a are nb[nb_start[a] .. nb_start[a+1]).
  std::vector<std::array<int, 2>> edges;
  std::vector<int> nb_start, nb_fill, nb, nb_stamp;
  struct Range {
    const int *b, *e;
    const int* begin() const { return b; }
    const int* end() const { return e; }
  };
  Range neighbours(size_t id) const {
    return {nb.data() + nb_start[id], nb.data() + nb_start[id + 1]};
  }
  struct Acc {  // a cluster while it grows
    Eigen::Vector3f weighted = Eigen::Vector3f::Zero();
    int support = 0;
    int leaves = 0;
  };
  std::vector<Acc> acc;
  std::vector<int> remap, motion_count;
  std::vector<Eigen::Vector3d> motion_sum;
  std::vector<Eigen::Vector3f> static_cands, dynamic_cands;  // per-leaf label candidates
};

GmcClassifier::GmcClassifier(const GmcParams& params)
    : params_(params), ws_(std::make_shared<Workspace>()) {}

namespace {

std::int32_t packCode(int bx, int by, int bz) {
  return ((bx + kBinLimit) * kBinSpan + (by + kBinLimit)) * kBinSpan + (bz + kBinLimit);
}

}  // namespace

GmcResult GmcClassifier::classify(const std::vector<MotionMatch>& matches,
                                  const Isometry& T_ref_cur, int image_width, int image_height) {
  GmcResult result;
  classify(matches, T_ref_cur, image_width, image_height, result);
  return result;
}

void GmcClassifier::classify(const std::vector<MotionMatch>& matches, const Isometry& T_ref_cur,
                             int image_width, int image_height, GmcResult& result) {
  const size_t n = matches.size();
  // Reset every field but keep the vectors' capacity.
  result.labels.assign(n, MotionLabel::Undecided);
  result.cells.clear();
  result.clusters.clear();
  result.static_cluster = -1;
  result.static_fallback = false;
  result.iterations = 0;
  result.grid_cols = result.grid_rows = 0;
  result.num_static = result.num_dynamic = result.num_undecided = 0;
  if (n == 0 || image_width <= 0 || image_height <= 0) return;
  Workspace& w = *ws_;
  const GmcParams& p = params_;

  // --- Eq. (3): depth-normalised 3-D residual, expressed in units of the pattern interval.
  w.e.resize(n);
  w.valid.assign(n, 0);
  w.code.resize(n);
  const Eigen::Matrix3d R = T_ref_cur.linear();
  const Eigen::Vector3d t = T_ref_cur.translation();
  const float inv_int[3] = {static_cast<float>(1.0 / p.e_int_x),
                            p.use_y ? static_cast<float>(1.0 / p.e_int_y) : 0.f,
                            static_cast<float>(1.0 / p.e_int_z)};
  const bool squared = p.z_depth_power == 2.0;  // the default; avoids pow() per match
  auto depth_scale = [&](double d) { return squared ? d * d : std::pow(d, p.z_depth_power); };
  int num_valid = 0;
  for (size_t i = 0; i < n; ++i) {
    const MotionMatch& m = matches[i];
    const bool ok = m.point_ref.allFinite() && m.point_cur.allFinite() && m.point_cur.z() > 0 &&
                    m.point_ref.z() > 0 && m.pixel.allFinite() && m.pixel.x() >= 0 &&
                    m.pixel.y() >= 0 && m.pixel.x() < image_width && m.pixel.y() < image_height;
    if (!ok) continue;
    const Eigen::Vector3d r = m.point_ref - (R * m.point_cur + t);
    // Eq. (3), refined with the covariance structure the paper cites (Beder & Steffen):
    // the residual is split along the viewing ray (depth noise, ~d^2 on a Kinect) and
    // across it (keypoint noise, ~d), each normalised by the point's distance d to its
    // own power. Across-ray axes keep the camera's x (horizontal) and y (vertical) sense.
    const double d = m.point_cur.norm();
    const Eigen::Vector3d ray = m.point_cur / d;
    const Eigen::Vector3d across_x = Eigen::Vector3d::UnitY().cross(ray).normalized();
    const Eigen::Vector3d across_y = ray.cross(across_x);
    w.e[i] = Eigen::Vector3f(
        static_cast<float>(p.alpha * r.dot(across_x) / d) * inv_int[0],
        static_cast<float>(p.alpha * r.dot(across_y) / d) * inv_int[1],
        static_cast<float>(p.alpha * r.dot(ray) / depth_scale(d)) * inv_int[2]);
    for (int b = 0; b < kBinnings; ++b)
      w.code[i][static_cast<size_t>(b)] =
          packCode(clampBin(w.e[i].x() - kShift[b][0]), clampBin(w.e[i].y() - kShift[b][1]),
                   clampBin(w.e[i].z() - kShift[b][2]));
    w.valid[i] = 1;
    ++num_valid;
  }
  if (!p.enabled) {
    for (size_t i = 0; i < n; ++i)
      if (w.valid[i]) result.labels[i] = MotionLabel::Static;
    result.num_static = num_valid;
    result.num_undecided = static_cast<int>(n) - num_valid;
    return;
  }

  // --- Alg. 1 l.4-8: grid cells; matches sorted by cell (counting sort, no allocation).
  // The paper's 20 x 15 grid assumes ORB-SLAM-dense features; with fewer matches the
  // cells would hold too few points to vote, so the grid is coarsened (aspect kept).
  int gx = p.grid_cols, gy = p.grid_rows;
  const double density = static_cast<double>(num_valid) / (gx * gy);
  if (p.min_matches_per_cell > 0 && density < p.min_matches_per_cell) {
    const double f = std::sqrt(density / p.min_matches_per_cell);
    gx = std::max(2, static_cast<int>(std::lround(gx * f)));
    gy = std::max(2, static_cast<int>(std::lround(gy * f)));
  }
  result.grid_cols = gx;
  result.grid_rows = gy;
  const int num_cells = gx * gy;
  auto cellOf = [&](const MotionMatch& m) {
    const int cx = std::min(gx - 1, static_cast<int>(m.pixel.x() * gx / image_width));
    const int cy = std::min(gy - 1, static_cast<int>(m.pixel.y() * gy / image_height));
    return cy * gx + cx;
  };
  w.cell_start.assign(static_cast<size_t>(num_cells) + 1, 0);
  for (size_t i = 0; i < n; ++i)
    if (w.valid[i]) ++w.cell_start[static_cast<size_t>(cellOf(matches[i])) + 1];
  for (int c = 0; c < num_cells; ++c) w.cell_start[static_cast<size_t>(c) + 1] += w.cell_start[static_cast<size_t>(c)];
  w.cell_fill.assign(w.cell_start.begin(), w.cell_start.end() - 1);
  w.items.resize(static_cast<size_t>(num_valid));
  for (size_t i = 0; i < n; ++i)
    if (w.valid[i]) w.items[static_cast<size_t>(w.cell_fill[static_cast<size_t>(cellOf(matches[i]))]++)] = static_cast<int>(i);

  // --- Alg. 1 l.9-11 for one leaf: winner and runner-up pattern in each of the four
  // tables; the leaf keeps the table whose winner holds most points (a motion on a bin
  // border of one table sits in the middle of a bin of a shifted one).
  auto vote = [&](Workspace::Leaf& leaf) {
    leaf.winner_count = 0;
    leaf.second_count = 0;
    for (int b = 0; b < kBinnings; ++b) {
      w.sort_buf.clear();
      for (int k = 0; k < leaf.count; ++k)
        w.sort_buf.push_back(w.code[static_cast<size_t>(w.items[static_cast<size_t>(leaf.first + k)])][static_cast<size_t>(b)]);
      std::sort(w.sort_buf.begin(), w.sort_buf.end());
      int best = 0, second = 0;
      std::int32_t best_code = 0;
      for (size_t s = 0; s < w.sort_buf.size();) {
        size_t e = s;
        while (e < w.sort_buf.size() && w.sort_buf[e] == w.sort_buf[s]) ++e;
        const int run = static_cast<int>(e - s);
        if (run > best) {
          second = best;
          best = run;
          best_code = w.sort_buf[s];
        } else if (run > second) {
          second = run;
        }
        s = e;
      }
      if (best > leaf.winner_count) {  // ties keep the earlier (unshifted) table
        leaf.winner_count = best;
        leaf.second_count = second;
        leaf.winner = best_code;
        leaf.binning = b;
      }
    }
  };

  // --- Quadtree (Sec. 3.3): split while the winner holds < p_min * n_i and n_i > n_min.
  w.leaves.clear();
  const int finest = 1 << p.max_depth;
  std::vector<int>& stack = w.queue;
  for (int c = 0; c < num_cells; ++c) {
    const int cx = c % gx, cy = c / gx;
    Workspace::Leaf root{};
    root.x0 = cx * image_width / gx;
    root.x1 = (cx + 1) * image_width / gx;
    root.y0 = cy * image_height / gy;
    root.y1 = (cy + 1) * image_height / gy;
    root.depth = 0;
    root.first = w.cell_start[static_cast<size_t>(c)];
    root.count = w.cell_start[static_cast<size_t>(c) + 1] - root.first;
    w.leaves.push_back(root);
    stack.assign(1, static_cast<int>(w.leaves.size()) - 1);
    while (!stack.empty()) {
      const int id = stack.back();
      stack.pop_back();
      Workspace::Leaf leaf = w.leaves[static_cast<size_t>(id)];
      if (leaf.count > 0) vote(leaf);
      w.leaves[static_cast<size_t>(id)] = leaf;
      const bool split = leaf.count > p.n_min && leaf.winner_count < p.p_min * leaf.count &&
                         leaf.depth < p.max_depth && leaf.x1 - leaf.x0 >= 2 && leaf.y1 - leaf.y0 >= 2;
      if (!split) continue;
      // Partition the leaf's items into four quadrants, in place.
      const int mx = (leaf.x0 + leaf.x1) / 2, my = (leaf.y0 + leaf.y1) / 2;
      auto quadrant = [&](int i) {
        const auto& px = matches[static_cast<size_t>(i)].pixel;
        return (px.x() >= mx ? 1 : 0) + (px.y() >= my ? 2 : 0);
      };
      w.scratch.assign(w.items.begin() + leaf.first, w.items.begin() + leaf.first + leaf.count);
      int pos = leaf.first;
      std::array<int, 4> start{}, count{};
      for (int q = 0; q < 4; ++q) {
        start[static_cast<size_t>(q)] = pos;
        for (int i : w.scratch)
          if (quadrant(i) == q) w.items[static_cast<size_t>(pos++)] = i;
        count[static_cast<size_t>(q)] = pos - start[static_cast<size_t>(q)];
      }
      // The parent is replaced by its first child; the others are appended.
      for (int q = 0; q < 4; ++q) {
        Workspace::Leaf child{};
        child.x0 = (q & 1) ? mx : leaf.x0;
        child.x1 = (q & 1) ? leaf.x1 : mx;
        child.y0 = (q & 2) ? my : leaf.y0;
        child.y1 = (q & 2) ? leaf.y1 : my;
        child.depth = leaf.depth + 1;
        child.first = start[static_cast<size_t>(q)];
        child.count = count[static_cast<size_t>(q)];
        if (q == 0) {
          w.leaves[static_cast<size_t>(id)] = child;
          stack.push_back(id);
        } else {
          w.leaves.push_back(child);
          stack.push_back(static_cast<int>(w.leaves.size()) - 1);
        }
      }
    }
  }

  // Leaf motion: mean residual of the members of its winning pattern.
  auto inWinner = [&](const Workspace::Leaf& leaf, int i) {
    return w.code[static_cast<size_t>(i)][static_cast<size_t>(leaf.binning)] == leaf.winner;
  };
  for (auto& leaf : w.leaves) {
    leaf.votes = leaf.count >= p.min_cell_points;
    leaf.cluster = -1;
    if (leaf.count == 0) continue;
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    for (int k = 0; k < leaf.count; ++k) {
      const int i = w.items[static_cast<size_t>(leaf.first + k)];
      if (inWinner(leaf, i)) sum += w.e[static_cast<size_t>(i)];
    }
    leaf.motion = sum / static_cast<float>(std::max(1, leaf.winner_count));
  }

  // --- Adjacency of leaves through a raster at the finest quadtree resolution.
  const int rw = gx * finest, rh = gy * finest;
  w.raster.assign(static_cast<size_t>(rw * rh), -1);
  const size_t num_leaves = w.leaves.size();
  for (size_t id = 0; id < num_leaves; ++id) {
    const auto& leaf = w.leaves[id];
    const int u0 = static_cast<int>(std::lround(static_cast<double>(leaf.x0) * rw / image_width));
    const int u1 = static_cast<int>(std::lround(static_cast<double>(leaf.x1) * rw / image_width));
    const int v0 = static_cast<int>(std::lround(static_cast<double>(leaf.y0) * rh / image_height));
    const int v1 = static_cast<int>(std::lround(static_cast<double>(leaf.y1) * rh / image_height));
    for (int v = v0; v < std::max(v1, v0 + 1) && v < rh; ++v)
      for (int u = u0; u < std::max(u1, u0 + 1) && u < rw; ++u) w.raster[static_cast<size_t>(v * rw + u)] = static_cast<int>(id);
  }
  w.edges.clear();
  auto link = [&](int a, int b) {
    if (a < 0 || b < 0 || a == b) return;
    w.edges.push_back({a, b});
    w.edges.push_back({b, a});
  };
  for (int v = 0; v < rh; ++v)
    for (int u = 0; u < rw; ++u) {
      const int a = w.raster[static_cast<size_t>(v * rw + u)];
      if (u + 1 < rw) link(a, w.raster[static_cast<size_t>(v * rw + u + 1)]);
      if (v + 1 < rh) link(a, w.raster[static_cast<size_t>((v + 1) * rw + u)]);
      if (u + 1 < rw && v + 1 < rh) link(a, w.raster[static_cast<size_t>((v + 1) * rw + u + 1)]);
      if (u > 0 && v + 1 < rh) link(a, w.raster[static_cast<size_t>((v + 1) * rw + u - 1)]);
    }
  // Counting sort of the edges by their first leaf, duplicates dropped with a stamp.
  w.nb_start.assign(num_leaves + 1, 0);
  for (const auto& e : w.edges) ++w.nb_start[static_cast<size_t>(e[0]) + 1];
  for (size_t id = 0; id < num_leaves; ++id) w.nb_start[id + 1] += w.nb_start[id];
  w.nb_fill.assign(w.nb_start.begin(), w.nb_start.end() - 1);
  w.nb.resize(w.edges.size());
  for (const auto& e : w.edges) w.nb[static_cast<size_t>(w.nb_fill[static_cast<size_t>(e[0])]++)] = e[1];
  w.nb_stamp.assign(num_leaves, -1);
  int kept = 0;
  for (size_t id = 0; id < num_leaves; ++id) {
    const int first = w.nb_start[id], last = w.nb_start[id + 1];
    w.nb_start[id] = kept;
    for (int k = first; k < last; ++k) {
      const int b = w.nb[static_cast<size_t>(k)];
      if (w.nb_stamp[static_cast<size_t>(b)] == static_cast<int>(id)) continue;
      w.nb_stamp[static_cast<size_t>(b)] = static_cast<int>(id);
      w.nb[static_cast<size_t>(kept++)] = b;
    }
  }
  w.nb_start[num_leaves] = kept;

  // --- Alg. 2 merge with non-maximum suppression: leaves in decreasing support seed
  // clusters; a seed absorbs adjacent voting leaves whose motion lies within one
  // interval of the cluster's running mean (same pattern, whatever the binning).
  auto distance = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
    return (a - b).cwiseAbs().maxCoeff();  // in intervals, per-axis (Chebyshev)
  };
  auto compatible = [](const Eigen::Vector3f& a, const Eigen::Vector3f& b, float tol) {
    return std::abs(a.x() - b.x()) <= tol && std::abs(a.y() - b.y()) <= tol &&
           std::abs(a.z() - b.z()) <= tol;
  };
  const float merge_tol = static_cast<float>(p.merge_tolerance);
  w.order.clear();
  for (size_t id = 0; id < num_leaves; ++id)
    if (w.leaves[id].votes) w.order.push_back(static_cast<int>(id));
  // Decreasing support, ties by leaf id (std::stable_sort would allocate a buffer).
  std::sort(w.order.begin(), w.order.end(), [&](int a, int b) {
    const int ca = w.leaves[static_cast<size_t>(a)].winner_count;
    const int cb = w.leaves[static_cast<size_t>(b)].winner_count;
    return ca != cb ? ca > cb : a < b;
  });
  using Acc = Workspace::Acc;
  std::vector<Acc>& acc = w.acc;
  acc.clear();
  for (int seed : w.order) {
    if (w.leaves[static_cast<size_t>(seed)].cluster >= 0) continue;
    const int cid = static_cast<int>(acc.size());
    acc.push_back({});
    Acc& a = acc.back();
    auto absorb = [&](int id) {
      auto& leaf = w.leaves[static_cast<size_t>(id)];
      leaf.cluster = cid;
      a.weighted += leaf.motion * static_cast<float>(leaf.winner_count);
      a.support += leaf.winner_count;
      ++a.leaves;
    };
    absorb(seed);
    w.queue.assign(1, seed);
    while (!w.queue.empty()) {
      const int id = w.queue.back();
      w.queue.pop_back();
      for (int nb : w.neighbours(static_cast<size_t>(id))) {
        auto& leaf = w.leaves[static_cast<size_t>(nb)];
        if (!leaf.votes || leaf.cluster >= 0) continue;
        const Eigen::Vector3f mean = a.weighted / static_cast<float>(a.support);
        if (!compatible(leaf.motion, mean, merge_tol)) continue;
        absorb(nb);
        w.queue.push_back(nb);
      }
    }
  }
  // "Until the assignment stops changing": leaves re-join the compatible adjacent cluster
  // with most support (the greedy pass above depends on seed order).
  for (int round = 0; round < p.max_rounds; ++round) {
    ++result.iterations;
    bool changed = false;
    for (int id : w.order) {
      auto& leaf = w.leaves[static_cast<size_t>(id)];
      int best = leaf.cluster;
      for (int nb : w.neighbours(static_cast<size_t>(id))) {
        const int c = w.leaves[static_cast<size_t>(nb)].cluster;
        if (c < 0 || c == best) continue;
        const Eigen::Vector3f mean = acc[static_cast<size_t>(c)].weighted / static_cast<float>(acc[static_cast<size_t>(c)].support);
        if (acc[static_cast<size_t>(c)].support > acc[static_cast<size_t>(best)].support &&
            compatible(leaf.motion, mean, merge_tol))
          best = c;
      }
      if (best != leaf.cluster) {
        auto& from = acc[static_cast<size_t>(leaf.cluster)];
        auto& to = acc[static_cast<size_t>(best)];
        const float wc = static_cast<float>(leaf.winner_count);
        from.weighted -= leaf.motion * wc;
        from.support -= leaf.winner_count;
        --from.leaves;
        to.weighted += leaf.motion * wc;
        to.support += leaf.winner_count;
        ++to.leaves;
        leaf.cluster = best;
        changed = true;
      }
    }
    if (!changed) break;
  }

  // Clusters: drop small ones, pick the static background (Sec. 3.3 prior).
  std::vector<int>& remap = w.remap;
  remap.assign(acc.size(), -1);
  for (size_t c = 0; c < acc.size(); ++c) {
    if (acc[c].support < p.min_cluster_size || acc[c].leaves == 0) continue;
    remap[c] = static_cast<int>(result.clusters.size());
    GmcCluster cl;
    cl.support = acc[c].support;
    const Eigen::Vector3f mean = acc[c].weighted / static_cast<float>(acc[c].support);
    cl.mean_residual = mean.cast<double>();
    result.clusters.push_back(cl);
  }
  // The background is the cluster near zero motion backed by most points; other clusters
  // near zero motion are background fragments cut off by a mover.
  const double static_tol = p.static_tolerance;
  auto nearZero = [&](const Eigen::Vector3d& m) { return m.cwiseAbs().maxCoeff() <= static_tol; };
  for (size_t c = 0; c < result.clusters.size(); ++c) {
    auto& cl = result.clusters[c];
    if (!nearZero(cl.mean_residual)) continue;
    cl.is_static = true;
    if (result.static_cluster < 0 ||
        cl.support > result.clusters[static_cast<size_t>(result.static_cluster)].support)
      result.static_cluster = static_cast<int>(c);
  }
  if (result.static_cluster < 0 && !result.clusters.empty()) {
    // No cluster near zero motion: the initial guess is off. Fall back to the paper's
    // prior that the largest motion cluster is the background.
    result.static_fallback = true;
    int best = 0;
    for (size_t c = 1; c < result.clusters.size(); ++c)
      if (result.clusters[c].support > result.clusters[static_cast<size_t>(best)].support) best = static_cast<int>(c);
    result.static_cluster = best;
    const Eigen::Vector3d ref = result.clusters[static_cast<size_t>(best)].mean_residual;
    for (auto& cl : result.clusters)
      cl.is_static = nearZero(cl.mean_residual - ref);
  }
  Eigen::Vector3f static_motion = Eigen::Vector3f::Zero();
  if (result.static_cluster >= 0)
    static_motion = result.clusters[static_cast<size_t>(result.static_cluster)].mean_residual.cast<float>();

  // --- Per-match labels. The leaf's cluster decides; a match contradicting it clearly
  // (own residual within half an interval of the other class) is relabelled.
  std::vector<Eigen::Vector3d>& motion_sum = w.motion_sum;
  std::vector<int>& motion_count = w.motion_count;
  motion_sum.assign(result.clusters.size(), Eigen::Vector3d::Zero());
  motion_count.assign(result.clusters.size(), 0);
  for (auto& leaf : w.leaves)
    leaf.cluster = leaf.cluster >= 0 ? remap[static_cast<size_t>(leaf.cluster)] : -1;
  for (size_t id = 0; id < num_leaves; ++id) {
    auto& leaf = w.leaves[id];
    const int cl = leaf.cluster;
    if (leaf.count == 0) continue;
    const bool leaf_static = cl >= 0 && result.clusters[static_cast<size_t>(cl)].is_static;
    // Candidate motions for the leaf's matches: the static background, the leaf's own
    // cluster and the clusters of adjacent leaves; each match takes the nearest, and one
    // far from all of them stays Undecided. A static leaf's motion stands for local
    // background (a slightly wrong guess makes it vary across the image) only while it
    // is close to the global one.
    w.static_cands.assign(1, static_motion);
    w.dynamic_cands.clear();
    if (leaf_static && distance(leaf.motion, static_motion) <= 0.5f)
      w.static_cands.push_back(leaf.motion);
    if (cl >= 0 && !leaf_static) w.dynamic_cands.push_back(leaf.motion);
    for (int nb : w.neighbours(id)) {
      const auto& other_leaf = w.leaves[static_cast<size_t>(nb)];
      const int c = other_leaf.cluster;
      if (c < 0) continue;
      if (!result.clusters[static_cast<size_t>(c)].is_static)
        w.dynamic_cands.push_back(other_leaf.motion);
      else if (distance(other_leaf.motion, static_motion) <= 0.5f)
        w.static_cands.push_back(other_leaf.motion);
    }
    for (int k = 0; k < leaf.count; ++k) {
      const int i = w.items[static_cast<size_t>(leaf.first + k)];
      const Eigen::Vector3f& e = w.e[static_cast<size_t>(i)];
      float best_static = std::numeric_limits<float>::max();
      float best_dynamic = std::numeric_limits<float>::max();
      for (const auto& c : w.static_cands) best_static = std::min(best_static, distance(e, c));
      for (const auto& c : w.dynamic_cands) best_dynamic = std::min(best_dynamic, distance(e, c));
      MotionLabel label = MotionLabel::Undecided;
      const float reach = cl >= 0 ? 2.0f : 1.0f;  // in intervals
      if (result.static_cluster >= 0 || best_dynamic < reach) {
        if (best_static <= best_dynamic && best_static <= reach)
          label = MotionLabel::Static;
        else if (best_dynamic < best_static && (best_dynamic <= reach || (cl >= 0 && !leaf_static)))
          label = MotionLabel::Dynamic;
      }
      result.labels[static_cast<size_t>(i)] = label;
      if (cl >= 0 && inWinner(leaf, i)) {
        const MotionMatch& m = matches[static_cast<size_t>(i)];
        motion_sum[static_cast<size_t>(cl)] += m.point_ref - T_ref_cur * m.point_cur;
        ++motion_count[static_cast<size_t>(cl)];
      }
    }
  }
  for (size_t c = 0; c < result.clusters.size(); ++c)
    if (motion_count[c] > 0) result.clusters[c].mean_motion = motion_sum[c] / motion_count[c];

  // Output cells.
  result.cells.reserve(num_leaves);
  for (const auto& leaf : w.leaves) {
    GmcCell cell;
    cell.x0 = leaf.x0;
    cell.y0 = leaf.y0;
    cell.x1 = leaf.x1;
    cell.y1 = leaf.y1;
    cell.depth = leaf.depth;
    cell.num_points = leaf.count;
    cell.binning = leaf.binning;
    const int code = leaf.winner;
    cell.pattern_z = code % kBinSpan - kBinLimit;
    cell.pattern_y = (code / kBinSpan) % kBinSpan - kBinLimit;
    cell.pattern_x = code / (kBinSpan * kBinSpan) - kBinLimit;
    cell.winner_count = leaf.winner_count;
    cell.second_count = leaf.second_count;
    cell.motion = leaf.motion;
    cell.cluster = leaf.cluster;
    result.cells.push_back(cell);
  }
  for (auto l : result.labels) {
    if (l == MotionLabel::Static) ++result.num_static;
    else if (l == MotionLabel::Dynamic) ++result.num_dynamic;
    else ++result.num_undecided;
  }
}

}  // namespace gmc
