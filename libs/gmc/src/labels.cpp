// Per-match labels from the leaves' clusters, and the public cells.
#include <limits>

#include "classify_steps.h"

namespace gmc::detail {
namespace {

/// Candidate motions for a leaf's matches: the static background, the leaf's own cluster
/// and the clusters of adjacent leaves. A static leaf's motion stands for local background
/// (a slightly wrong guess makes it vary across the image) only while it is close to the
/// global one.
void leafCandidates(size_t id, const std::vector<Leaf>& leaves, const Adjacency& adj, const GmcResult& result,
                    const Eigen::Vector3f& static_motion, bool leaf_static, LabelBuffers& buf) {
  const Leaf& leaf = leaves[id];
  buf.static_cands.assign(1, static_motion);
  buf.dynamic_cands.clear();
  if (leaf_static && chebyshev(leaf.motion, static_motion) <= 0.5f) buf.static_cands.push_back(leaf.motion);
  if (leaf.cluster >= 0 && !leaf_static) buf.dynamic_cands.push_back(leaf.motion);
  for (int nb : adj.neighbours(id)) {
    const auto& other = leaves[static_cast<size_t>(nb)];
    if (other.cluster < 0) continue;
    if (!result.clusters[static_cast<size_t>(other.cluster)].is_static)
      buf.dynamic_cands.push_back(other.motion);
    else if (chebyshev(other.motion, static_motion) <= 0.5f)
      buf.static_cands.push_back(other.motion);
  }
}

float nearest(const Eigen::Vector3f& e, const std::vector<Eigen::Vector3f>& candidates) {
  float best = std::numeric_limits<float>::max();
  for (const auto& c : candidates) best = std::min(best, chebyshev(e, c));
  return best;
}

/// The nearest candidate decides; a match far from all of them stays Undecided.
MotionLabel labelOf(const Eigen::Vector3f& e, const LabelBuffers& buf, bool in_cluster, bool leaf_static,
                    bool has_background) {
  const float best_static = nearest(e, buf.static_cands);
  const float best_dynamic = nearest(e, buf.dynamic_cands);
  const float reach = in_cluster ? 2.0f : 1.0f;  // in intervals
  if (!has_background && best_dynamic >= reach) return MotionLabel::Undecided;
  if (best_static <= best_dynamic && best_static <= reach) return MotionLabel::Static;
  if (best_dynamic < best_static && (best_dynamic <= reach || (in_cluster && !leaf_static)))
    return MotionLabel::Dynamic;
  return MotionLabel::Undecided;
}

}  // namespace

void labelMatches(const std::vector<MotionMatch>& matches, const Isometry& T_ref_cur, const Residuals& res,
                  const std::vector<int>& items, const std::vector<Leaf>& leaves, const Adjacency& adj,
                  LabelBuffers& buf, GmcResult& result) {
  buf.motion_sum.assign(result.clusters.size(), Eigen::Vector3d::Zero());
  buf.motion_count.assign(result.clusters.size(), 0);
  Eigen::Vector3f static_motion = Eigen::Vector3f::Zero();
  if (result.static_cluster >= 0)
    static_motion = result.clusters[static_cast<size_t>(result.static_cluster)].mean_residual.cast<float>();
  for (size_t id = 0; id < leaves.size(); ++id) {
    const Leaf& leaf = leaves[id];
    const int cl = leaf.cluster;
    if (leaf.count == 0) continue;
    const bool leaf_static = cl >= 0 && result.clusters[static_cast<size_t>(cl)].is_static;
    leafCandidates(id, leaves, adj, result, static_motion, leaf_static, buf);
    for (int k = 0; k < leaf.count; ++k) {
      const int i = items[static_cast<size_t>(leaf.first + k)];
      result.labels[static_cast<size_t>(i)] =
          labelOf(res.e[static_cast<size_t>(i)], buf, cl >= 0, leaf_static, result.static_cluster >= 0);
      if (cl < 0 || !inWinner(leaf, res, i)) continue;
      const MotionMatch& m = matches[static_cast<size_t>(i)];
      buf.motion_sum[static_cast<size_t>(cl)] += m.point_ref - T_ref_cur * m.point_cur;
      ++buf.motion_count[static_cast<size_t>(cl)];
    }
  }
  for (size_t c = 0; c < result.clusters.size(); ++c)
    if (buf.motion_count[c] > 0) result.clusters[c].mean_motion = buf.motion_sum[c] / buf.motion_count[c];
}

void writeCells(const std::vector<Leaf>& leaves, GmcResult& result) {
  result.cells.reserve(leaves.size());
  for (const auto& leaf : leaves) {
    GmcCell cell;
    cell.x0 = leaf.x0;
    cell.y0 = leaf.y0;
    cell.x1 = leaf.x1;
    cell.y1 = leaf.y1;
    cell.depth = leaf.depth;
    cell.num_points = leaf.count;
    cell.binning = leaf.binning;
    const auto pattern = unpackCode(leaf.winner);
    cell.pattern_x = pattern[0];
    cell.pattern_y = pattern[1];
    cell.pattern_z = pattern[2];
    cell.winner_count = leaf.winner_count;
    cell.second_count = leaf.second_count;
    cell.motion = leaf.motion;
    cell.cluster = leaf.cluster;
    result.cells.push_back(cell);
  }
}

void countLabels(GmcResult& result) {
  for (auto l : result.labels) {
    if (l == MotionLabel::Static) ++result.num_static;
    else if (l == MotionLabel::Dynamic) ++result.num_dynamic;
    else ++result.num_undecided;
  }
}

}  // namespace gmc::detail
