// GMS: grid-based motion statistics (Bian et al., CVPR 2017), written from the paper.
// A true match's 3x3 cell neighbourhood maps to the same neighbourhood in the other
// image, so its score (matches agreeing with its cell pair) follows B(n, p_true) while a
// false match's follows B(n, p_false); thresholding at alpha*sqrt(n) separates them.
#include "gmc/gmc/gms.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace gmc {
namespace {

// The 3x3 neighbourhood as a ring (clockwise from top-left) plus the centre, so that a
// rotation of the second image is a shift of the ring.
constexpr std::array<std::array<int, 2>, 8> kRing = {
    {{-1, -1}, {0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}}};

struct Grid {
  int cols = 0, rows = 0;
  double sx = 0, sy = 0;        // cells per pixel
  double shift_x = 0, shift_y = 0;  // in cells
  int cell(float x, float y) const {
    const int cx = std::clamp(static_cast<int>(x * sx + shift_x), 0, cols - 1);
    const int cy = std::clamp(static_cast<int>(y * sy + shift_y), 0, rows - 1);
    return cy * cols + cx;
  }
};

class GmsRun {
 public:
  GmsRun(const std::vector<GmsKeypoint>& kp1, const std::vector<GmsKeypoint>& kp2,
         const std::vector<GmsMatch>& matches, double alpha)
      : kp1_(kp1), kp2_(kp2), matches_(matches), alpha_(alpha) {}

  /// Marks inliers for one left-grid shift, right-grid scale and rotation; returns count.
  int run(const Grid& left, const Grid& right, int rotation, std::vector<std::uint8_t>& inlier) {
    assignCells(left, right);
    countPairs(left.cols * left.rows, static_cast<size_t>(right.cols * right.rows));
    chooseBestPairs(left, right, rotation);
    int count = 0;
    for (size_t i = 0; i < matches_.size(); ++i)
      if (best_[static_cast<size_t>(c1_[i])] == c2_[i]) {
        if (!inlier[i]) ++count;
        inlier[i] = 1;
      }
    return count;
  }

 private:
  /// Cell of every match in both images; matches per left cell.
  void assignCells(const Grid& left, const Grid& right) {
    const size_t m = matches_.size();
    c1_.resize(m);
    c2_.resize(m);
    points_per_cell_.assign(static_cast<size_t>(left.cols * left.rows), 0);
    for (size_t i = 0; i < m; ++i) {
      const auto& a = kp1_[static_cast<size_t>(matches_[i].query)];
      const auto& b = kp2_[static_cast<size_t>(matches_[i].train)];
      c1_[i] = left.cell(a.x, a.y);
      c2_[i] = right.cell(b.x, b.y);
      ++points_per_cell_[static_cast<size_t>(c1_[i])];
    }
  }

  /// Pair counts, grouped by left cell: a counting sort by left cell, then per left cell
  /// one pass with a counter per right cell (stamped, so it is never cleared): O(N + cells).
  /// Afterwards the pairs (c2, count) of left cell a are pairs_[pair_start_[a] .. [a+1]).
  void countPairs(int n1, size_t n2) {
    const size_t m = matches_.size();
    pair_start_.assign(static_cast<size_t>(n1) + 1, 0);
    for (size_t i = 0; i < m; ++i) ++pair_start_[static_cast<size_t>(c1_[i]) + 1];
    for (int c = 0; c < n1; ++c) pair_start_[static_cast<size_t>(c) + 1] += pair_start_[static_cast<size_t>(c)];
    order_.resize(m);
    fill_.assign(pair_start_.begin(), pair_start_.end() - 1);
    for (size_t i = 0; i < m; ++i) order_[static_cast<size_t>(fill_[static_cast<size_t>(c1_[i])]++)] = static_cast<int>(i);
    right_count_.assign(n2, 0);
    right_stamp_.assign(n2, -1);
    pairs_.clear();
    for (int a = 0; a < n1; ++a) {
      const int first_pair = static_cast<int>(pairs_.size());
      for (int k = pair_start_[static_cast<size_t>(a)]; k < pair_start_[static_cast<size_t>(a) + 1]; ++k) {
        const auto b = static_cast<size_t>(c2_[static_cast<size_t>(order_[static_cast<size_t>(k)])]);
        if (right_stamp_[b] != a) {
          right_stamp_[b] = a;
          right_count_[b] = static_cast<int>(pairs_.size());
          pairs_.push_back({static_cast<int>(b), 0});
        }
        ++pairs_[static_cast<size_t>(right_count_[b])][1];
      }
      pair_start_[static_cast<size_t>(a)] = first_pair;
    }
    pair_start_[static_cast<size_t>(n1)] = static_cast<int>(pairs_.size());
  }

  int pairCount(int a, int b) const {
    for (int k = pair_start_[static_cast<size_t>(a)]; k < pair_start_[static_cast<size_t>(a) + 1]; ++k)
      if (pairs_[static_cast<size_t>(k)][0] == b) return pairs_[static_cast<size_t>(k)][1];
    return 0;
  }

  /// Best right cell of every left cell, kept (best_) when its neighbourhood score passes
  /// the alpha * sqrt(n) threshold; -1 otherwise.
  void chooseBestPairs(const Grid& left, const Grid& right, int rotation) {
    const int n1 = left.cols * left.rows;
    best_.assign(static_cast<size_t>(n1), -1);
    for (int a = 0; a < n1; ++a) {
      int best = -1, best_count = 0;
      for (int k = pair_start_[static_cast<size_t>(a)]; k < pair_start_[static_cast<size_t>(a) + 1]; ++k)
        if (pairs_[static_cast<size_t>(k)][1] > best_count) {
          best_count = pairs_[static_cast<size_t>(k)][1];
          best = pairs_[static_cast<size_t>(k)][0];
        }
      if (best < 0) continue;
      if (neighbourhoodPasses(left, right, rotation, a, best, best_count)) best_[static_cast<size_t>(a)] = best;
    }
  }

  /// Matches agreeing with the cell pair (a, b) and its 3x3 neighbourhood (the ring
  /// rotated by `rotation` in the right image) against alpha * sqrt(mean points per cell).
  bool neighbourhoodPasses(const Grid& left, const Grid& right, int rotation, int a, int b, int count) const {
    const int ax = a % left.cols, ay = a / left.cols, bx = b % right.cols, by = b / right.cols;
    double score = count, support = points_per_cell_[static_cast<size_t>(a)];
    for (int r = 0; r < 8; ++r) {
      const auto& da = kRing[static_cast<size_t>(r)];
      const auto& db = kRing[static_cast<size_t>((r + rotation) % 8)];
      const int nax = ax + da[0], nay = ay + da[1], nbx = bx + db[0], nby = by + db[1];
      if (nax < 0 || nay < 0 || nax >= left.cols || nay >= left.rows) continue;
      const int na = nay * left.cols + nax;
      support += points_per_cell_[static_cast<size_t>(na)];
      if (nbx < 0 || nby < 0 || nbx >= right.cols || nby >= right.rows) continue;
      score += pairCount(na, nby * right.cols + nbx);
    }
    return score > alpha_ * std::sqrt(support / 9.0);
  }

  const std::vector<GmsKeypoint>& kp1_;
  const std::vector<GmsKeypoint>& kp2_;
  const std::vector<GmsMatch>& matches_;
  double alpha_;
  std::vector<int> c1_, c2_, points_per_cell_, order_, pair_start_, fill_, best_;
  std::vector<int> right_count_, right_stamp_;  // per right cell: index into pairs_, owner
  std::vector<std::array<int, 2>> pairs_;
};

}  // namespace

std::vector<std::uint8_t> gmsFilter(const std::vector<GmsKeypoint>& keypoints1, int width1,
                                    int height1, const std::vector<GmsKeypoint>& keypoints2,
                                    int width2, int height2, const std::vector<GmsMatch>& matches,
                                    const GmsParams& params) {
  std::vector<std::uint8_t> best(matches.size(), 0);
  if (matches.empty() || width1 <= 0 || height1 <= 0 || width2 <= 0 || height2 <= 0) return best;
  for (const auto& m : matches)
    if (m.query < 0 || m.train < 0 || static_cast<size_t>(m.query) >= keypoints1.size() ||
        static_cast<size_t>(m.train) >= keypoints2.size())
      return best;  // malformed input: nothing is trusted

  // GMS assumes dense matches (the paper uses 10k features on a 20x20 grid). With the
  // sparser GFTT sets of RGB-D odometry, a coarser grid keeps the statistics meaningful.
  int cols = params.grid_cols, rows = params.grid_rows;
  const double density = static_cast<double>(matches.size()) / (cols * rows);
  if (params.min_matches_per_cell > 0 && density < params.min_matches_per_cell) {
    const double f = std::sqrt(density / params.min_matches_per_cell);
    cols = std::max(2, static_cast<int>(std::lround(cols * f)));
    rows = std::max(2, static_cast<int>(std::lround(rows * f)));
  }
  GmsRun run(keypoints1, keypoints2, matches, params.alpha);
  const std::vector<double> scales =
      params.with_scale ? std::vector<double>{0.5, 1.0 / std::sqrt(2.0), 1.0, std::sqrt(2.0), 2.0}
                        : std::vector<double>{1.0};
  const int rotations = params.with_rotation ? 8 : 1;
  int best_count = -1;
  std::vector<std::uint8_t> inlier(matches.size());
  for (double scale : scales) {
    Grid right;
    right.cols = std::max(1, static_cast<int>(std::lround(cols * scale)));
    right.rows = std::max(1, static_cast<int>(std::lround(rows * scale)));
    right.sx = static_cast<double>(right.cols) / width2;
    right.sy = static_cast<double>(right.rows) / height2;
    for (int rotation = 0; rotation < rotations; ++rotation) {
      std::fill(inlier.begin(), inlier.end(), 0);
      int count = 0;
      // Four left grids shifted by half a cell, so that a motion-coherent region cut by
      // a cell border in one grid is whole in another; inliers are the union.
      for (int s = 0; s < 4; ++s) {
        Grid left;
        left.cols = cols + 1;
        left.rows = rows + 1;
        left.sx = static_cast<double>(cols) / width1;
        left.sy = static_cast<double>(rows) / height1;
        left.shift_x = (s & 1) ? 0.5 : 0.0;
        left.shift_y = (s & 2) ? 0.5 : 0.0;
        count += run.run(left, right, rotation, inlier);
      }
      if (count > best_count) {
        best_count = count;
        best = inlier;
      }
    }
  }
  return best;
}

}  // namespace gmc
