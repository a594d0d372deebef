// Alg. 2: leaves merged into motion clusters with non-maximum suppression, re-assigned
// until stable, and the choice of the static background among the clusters.
#include "classify_steps.h"

namespace gmc::detail {
namespace {

/// Voting leaves in decreasing support, ties by leaf id (std::stable_sort would allocate).
void seedOrder(const std::vector<Leaf>& leaves, std::vector<int>& order) {
  order.clear();
  for (size_t id = 0; id < leaves.size(); ++id)
    if (leaves[id].votes) order.push_back(static_cast<int>(id));
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const int ca = leaves[static_cast<size_t>(a)].winner_count;
    const int cb = leaves[static_cast<size_t>(b)].winner_count;
    return ca != cb ? ca > cb : a < b;
  });
}

void absorb(Leaf& leaf, int cluster, ClusterAcc& acc) {
  leaf.cluster = cluster;
  acc.weighted += leaf.motion * static_cast<float>(leaf.winner_count);
  acc.support += leaf.winner_count;
  ++acc.leaves;
}

/// Grows cluster `cid` from `seed` over adjacent compatible voting leaves.
void growCluster(int seed, int cid, std::vector<Leaf>& leaves, const Adjacency& adj, float tol,
                 MergeBuffers& buf) {
  ClusterAcc& a = buf.acc[static_cast<size_t>(cid)];
  absorb(leaves[static_cast<size_t>(seed)], cid, a);
  buf.queue.assign(1, seed);
  while (!buf.queue.empty()) {
    const int id = buf.queue.back();
    buf.queue.pop_back();
    for (int nb : adj.neighbours(static_cast<size_t>(id))) {
      auto& leaf = leaves[static_cast<size_t>(nb)];
      if (!leaf.votes || leaf.cluster >= 0) continue;
      if (!compatible(leaf.motion, a.mean(), tol)) continue;
      absorb(leaf, cid, a);
      buf.queue.push_back(nb);
    }
  }
}

/// The compatible adjacent cluster with more support than the leaf's own, if any.
int bestAdjacentCluster(int id, const std::vector<Leaf>& leaves, const Adjacency& adj, float tol,
                        const std::vector<ClusterAcc>& acc) {
  const Leaf& leaf = leaves[static_cast<size_t>(id)];
  int best = leaf.cluster;
  for (int nb : adj.neighbours(static_cast<size_t>(id))) {
    const int c = leaves[static_cast<size_t>(nb)].cluster;
    if (c < 0 || c == best) continue;
    const ClusterAcc& candidate = acc[static_cast<size_t>(c)];
    if (candidate.support > acc[static_cast<size_t>(best)].support && compatible(leaf.motion, candidate.mean(), tol))
      best = c;
  }
  return best;
}

void moveLeaf(Leaf& leaf, ClusterAcc& from, ClusterAcc& to) {
  const float wc = static_cast<float>(leaf.winner_count);
  from.weighted -= leaf.motion * wc;
  from.support -= leaf.winner_count;
  --from.leaves;
  to.weighted += leaf.motion * wc;
  to.support += leaf.winner_count;
  ++to.leaves;
}

}  // namespace

void mergeWithNms(std::vector<Leaf>& leaves, const Adjacency& adj, float merge_tolerance, MergeBuffers& buf) {
  seedOrder(leaves, buf.order);
  buf.acc.clear();
  for (int seed : buf.order) {
    if (leaves[static_cast<size_t>(seed)].cluster >= 0) continue;
    buf.acc.push_back({});
    growCluster(seed, static_cast<int>(buf.acc.size()) - 1, leaves, adj, merge_tolerance, buf);
  }
}

int reassignUntilStable(std::vector<Leaf>& leaves, const Adjacency& adj, float merge_tolerance, int max_rounds,
                        MergeBuffers& buf) {
  int rounds = 0;
  for (int round = 0; round < max_rounds; ++round) {
    ++rounds;
    bool changed = false;
    for (int id : buf.order) {
      auto& leaf = leaves[static_cast<size_t>(id)];
      const int best = bestAdjacentCluster(id, leaves, adj, merge_tolerance, buf.acc);
      if (best == leaf.cluster) continue;
      moveLeaf(leaf, buf.acc[static_cast<size_t>(leaf.cluster)], buf.acc[static_cast<size_t>(best)]);
      leaf.cluster = best;
      changed = true;
    }
    if (!changed) break;
  }
  return rounds;
}

namespace {

void keepLargeClusters(const std::vector<ClusterAcc>& acc, int min_cluster_size, std::vector<int>& remap,
                       GmcResult& result) {
  remap.assign(acc.size(), -1);
  for (size_t c = 0; c < acc.size(); ++c) {
    if (acc[c].support < min_cluster_size || acc[c].leaves == 0) continue;
    remap[c] = static_cast<int>(result.clusters.size());
    GmcCluster cl;
    cl.support = acc[c].support;
    cl.mean_residual = acc[c].mean().cast<double>();
    result.clusters.push_back(cl);
  }
}

int largestCluster(const std::vector<GmcCluster>& clusters) {
  int best = 0;
  for (size_t c = 1; c < clusters.size(); ++c)
    if (clusters[c].support > clusters[static_cast<size_t>(best)].support) best = static_cast<int>(c);
  return best;
}

}  // namespace

void chooseBackground(const std::vector<ClusterAcc>& acc, const GmcParams& p, std::vector<int>& remap,
                      GmcResult& result) {
  keepLargeClusters(acc, p.min_cluster_size, remap, result);
  // The background is the cluster near zero motion backed by most points; other clusters
  // near zero motion are background fragments cut off by a mover.
  auto nearZero = [&](const Eigen::Vector3d& m) { return m.cwiseAbs().maxCoeff() <= p.static_tolerance; };
  for (size_t c = 0; c < result.clusters.size(); ++c) {
    auto& cl = result.clusters[c];
    if (!nearZero(cl.mean_residual)) continue;
    cl.is_static = true;
    if (result.static_cluster < 0 || cl.support > result.clusters[static_cast<size_t>(result.static_cluster)].support)
      result.static_cluster = static_cast<int>(c);
  }
  if (result.static_cluster >= 0 || result.clusters.empty()) return;
  // No cluster near zero motion: the initial guess is off. Fall back to the paper's prior
  // that the largest motion cluster is the background.
  result.static_fallback = true;
  result.static_cluster = largestCluster(result.clusters);
  const Eigen::Vector3d ref = result.clusters[static_cast<size_t>(result.static_cluster)].mean_residual;
  for (auto& cl : result.clusters) cl.is_static = nearZero(cl.mean_residual - ref);
}

}  // namespace gmc::detail
