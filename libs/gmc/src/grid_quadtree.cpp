// The grid x pattern tensor (Alg. 1 l.4-11) and its quadtree refinement (Sec. 3.3).
#include "classify_steps.h"

namespace gmc::detail {

Grid chooseGrid(const GmcParams& p, int num_valid, int image_width, int image_height) {
  // The paper's 20 x 15 grid assumes ORB-SLAM-dense features; with fewer matches the
  // cells would hold too few points to vote.
  Grid g{p.grid_cols, p.grid_rows, image_width, image_height};
  const double density = static_cast<double>(num_valid) / (g.cols * g.rows);
  if (p.min_matches_per_cell > 0 && density < p.min_matches_per_cell) {
    const double f = std::sqrt(density / p.min_matches_per_cell);
    g.cols = std::max(2, static_cast<int>(std::lround(g.cols * f)));
    g.rows = std::max(2, static_cast<int>(std::lround(g.rows * f)));
  }
  return g;
}

void bucketByCell(const std::vector<MotionMatch>& matches, const Residuals& res, const Grid& grid,
                  CellBuckets& out) {
  const size_t num_cells = static_cast<size_t>(grid.cells());
  const size_t n = matches.size();
  out.start.assign(num_cells + 1, 0);
  for (size_t i = 0; i < n; ++i)
    if (res.valid[i]) ++out.start[static_cast<size_t>(grid.cellOf(matches[i].pixel)) + 1];
  for (size_t c = 0; c < num_cells; ++c) out.start[c + 1] += out.start[c];
  out.fill.assign(out.start.begin(), out.start.end() - 1);
  out.items.resize(static_cast<size_t>(res.num_valid));
  for (size_t i = 0; i < n; ++i)
    if (res.valid[i])
      out.items[static_cast<size_t>(out.fill[static_cast<size_t>(grid.cellOf(matches[i].pixel))]++)] =
          static_cast<int>(i);
}

namespace {

struct TableVote {
  int best = 0, second = 0;
  std::int32_t best_code = 0;
};

/// Most and second most frequent code of a sorted run of codes.
TableVote countRuns(const std::vector<std::int32_t>& sorted) {
  TableVote v;
  for (size_t s = 0; s < sorted.size();) {
    size_t e = s;
    while (e < sorted.size() && sorted[e] == sorted[s]) ++e;
    const int run = static_cast<int>(e - s);
    if (run > v.best) {
      v.second = v.best;
      v.best = run;
      v.best_code = sorted[s];
    } else if (run > v.second) {
      v.second = run;
    }
    s = e;
  }
  return v;
}

}  // namespace

void voteLeaf(Leaf& leaf, const std::vector<PatternCodes>& codes, const std::vector<int>& items,
              std::vector<std::int32_t>& sort_buf) {
  leaf.winner_count = 0;
  leaf.second_count = 0;
  for (int b = 0; b < kBinnings; ++b) {
    sort_buf.clear();
    for (int k = 0; k < leaf.count; ++k)
      sort_buf.push_back(codes[static_cast<size_t>(items[static_cast<size_t>(leaf.first + k)])][static_cast<size_t>(b)]);
    std::sort(sort_buf.begin(), sort_buf.end());
    const TableVote v = countRuns(sort_buf);
    if (v.best > leaf.winner_count) {  // ties keep the earlier (unshifted) table
      leaf.winner_count = v.best;
      leaf.second_count = v.second;
      leaf.winner = v.best_code;
      leaf.binning = b;
    }
  }
}

namespace {

Leaf rootLeaf(int cell, const Grid& g, const CellBuckets& buckets) {
  const int cx = cell % g.cols, cy = cell / g.cols;
  Leaf root{};
  root.x0 = cx * g.image_width / g.cols;
  root.x1 = (cx + 1) * g.image_width / g.cols;
  root.y0 = cy * g.image_height / g.rows;
  root.y1 = (cy + 1) * g.image_height / g.rows;
  root.depth = 0;
  root.first = buckets.start[static_cast<size_t>(cell)];
  root.count = buckets.start[static_cast<size_t>(cell) + 1] - root.first;
  return root;
}

bool shouldSplit(const Leaf& leaf, const GmcParams& p) {
  return leaf.count > p.n_min && leaf.winner_count < p.p_min * leaf.count && leaf.depth < p.max_depth &&
         leaf.x1 - leaf.x0 >= 2 && leaf.y1 - leaf.y0 >= 2;
}

/// The leaf's four children (quadrant q: bit 0 = right half, bit 1 = lower half), their
/// items partitioned in place in quadrant order.
std::array<Leaf, 4> splitLeaf(const Leaf& leaf, const std::vector<MotionMatch>& matches, std::vector<int>& items,
                              std::vector<int>& scratch) {
  const int mx = (leaf.x0 + leaf.x1) / 2, my = (leaf.y0 + leaf.y1) / 2;
  auto quadrant = [&](int i) {
    const auto& px = matches[static_cast<size_t>(i)].pixel;
    return (px.x() >= mx ? 1 : 0) + (px.y() >= my ? 2 : 0);
  };
  scratch.assign(items.begin() + leaf.first, items.begin() + leaf.first + leaf.count);
  std::array<Leaf, 4> children{};
  int pos = leaf.first;
  for (int q = 0; q < 4; ++q) {
    Leaf& child = children[static_cast<size_t>(q)];
    child.x0 = (q & 1) ? mx : leaf.x0;
    child.x1 = (q & 1) ? leaf.x1 : mx;
    child.y0 = (q & 2) ? my : leaf.y0;
    child.y1 = (q & 2) ? leaf.y1 : my;
    child.depth = leaf.depth + 1;
    child.first = pos;
    for (int i : scratch)
      if (quadrant(i) == q) items[static_cast<size_t>(pos++)] = i;
    child.count = pos - child.first;
  }
  return children;
}

}  // namespace

void splitQuadtree(const std::vector<MotionMatch>& matches, const Residuals& res, const Grid& grid,
                   const GmcParams& p, CellBuckets& buckets, std::vector<Leaf>& leaves, QuadtreeBuffers& buf) {
  leaves.clear();
  for (int c = 0; c < grid.cells(); ++c) {
    leaves.push_back(rootLeaf(c, grid, buckets));
    buf.stack.assign(1, static_cast<int>(leaves.size()) - 1);
    while (!buf.stack.empty()) {
      const int id = buf.stack.back();
      buf.stack.pop_back();
      Leaf leaf = leaves[static_cast<size_t>(id)];
      if (leaf.count > 0) voteLeaf(leaf, res.code, buckets.items, buf.sort_buf);
      leaves[static_cast<size_t>(id)] = leaf;
      if (!shouldSplit(leaf, p)) continue;
      // The parent is replaced by its first child; the others are appended.
      const auto children = splitLeaf(leaf, matches, buckets.items, buf.scratch);
      leaves[static_cast<size_t>(id)] = children[0];
      buf.stack.push_back(id);
      for (int q = 1; q < 4; ++q) {
        leaves.push_back(children[static_cast<size_t>(q)]);
        buf.stack.push_back(static_cast<int>(leaves.size()) - 1);
      }
    }
  }
}

void leafMotions(const Residuals& res, const std::vector<int>& items, int min_cell_points,
                 std::vector<Leaf>& leaves) {
  for (auto& leaf : leaves) {
    leaf.votes = leaf.count >= min_cell_points;
    leaf.cluster = -1;
    if (leaf.count == 0) continue;
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    for (int k = 0; k < leaf.count; ++k) {
      const int i = items[static_cast<size_t>(leaf.first + k)];
      if (inWinner(leaf, res, i)) sum += res.e[static_cast<size_t>(i)];
    }
    leaf.motion = sum / static_cast<float>(std::max(1, leaf.winner_count));
  }
}

}  // namespace gmc::detail
