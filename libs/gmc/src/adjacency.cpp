// Which leaves touch: needed by the merge (Alg. 2) and by the per-match labels.
#include "classify_steps.h"

namespace gmc::detail {
namespace {

/// Leaf id per unit of the finest quadtree level (every leaf covers whole units).
void rasterizeLeaves(const std::vector<Leaf>& leaves, const Grid& grid, int rw, int rh, std::vector<int>& raster) {
  raster.assign(static_cast<size_t>(rw * rh), -1);
  auto unit = [](int px, int units, int pixels) {
    return static_cast<int>(std::lround(static_cast<double>(px) * units / pixels));
  };
  for (size_t id = 0; id < leaves.size(); ++id) {
    const auto& leaf = leaves[id];
    const int u0 = unit(leaf.x0, rw, grid.image_width), u1 = unit(leaf.x1, rw, grid.image_width);
    const int v0 = unit(leaf.y0, rh, grid.image_height), v1 = unit(leaf.y1, rh, grid.image_height);
    for (int v = v0; v < std::max(v1, v0 + 1) && v < rh; ++v)
      for (int u = u0; u < std::max(u1, u0 + 1) && u < rw; ++u)
        raster[static_cast<size_t>(v * rw + u)] = static_cast<int>(id);
  }
}

/// Both directions of every pair of different leaves in 8-neighbouring units.
void collectEdges(const std::vector<int>& raster, int rw, int rh, std::vector<std::array<int, 2>>& edges) {
  edges.clear();
  auto link = [&](int a, int b) {
    if (a < 0 || b < 0 || a == b) return;
    edges.push_back({a, b});
    edges.push_back({b, a});
  };
  auto at = [&](int u, int v) { return raster[static_cast<size_t>(v * rw + u)]; };
  for (int v = 0; v < rh; ++v)
    for (int u = 0; u < rw; ++u) {
      const int a = at(u, v);
      if (u + 1 < rw) link(a, at(u + 1, v));
      if (v + 1 < rh) link(a, at(u, v + 1));
      if (u + 1 < rw && v + 1 < rh) link(a, at(u + 1, v + 1));
      if (u > 0 && v + 1 < rh) link(a, at(u - 1, v + 1));
    }
}

/// Counting sort of the edges by their first leaf, duplicates dropped with a stamp.
void edgesToCsr(size_t num_leaves, Adjacency& adj) {
  adj.nb_start.assign(num_leaves + 1, 0);
  for (const auto& e : adj.edges) ++adj.nb_start[static_cast<size_t>(e[0]) + 1];
  for (size_t id = 0; id < num_leaves; ++id) adj.nb_start[id + 1] += adj.nb_start[id];
  adj.nb_fill.assign(adj.nb_start.begin(), adj.nb_start.end() - 1);
  adj.nb.resize(adj.edges.size());
  for (const auto& e : adj.edges) adj.nb[static_cast<size_t>(adj.nb_fill[static_cast<size_t>(e[0])]++)] = e[1];
  adj.nb_stamp.assign(num_leaves, -1);
  int kept = 0;
  for (size_t id = 0; id < num_leaves; ++id) {
    const int first = adj.nb_start[id], last = adj.nb_start[id + 1];
    adj.nb_start[id] = kept;
    for (int k = first; k < last; ++k) {
      const int b = adj.nb[static_cast<size_t>(k)];
      if (adj.nb_stamp[static_cast<size_t>(b)] == static_cast<int>(id)) continue;
      adj.nb_stamp[static_cast<size_t>(b)] = static_cast<int>(id);
      adj.nb[static_cast<size_t>(kept++)] = b;
    }
  }
  adj.nb_start[num_leaves] = kept;
}

}  // namespace

void buildAdjacency(const std::vector<Leaf>& leaves, const Grid& grid, int max_depth, Adjacency& adj) {
  const int finest = 1 << max_depth;
  const int rw = grid.cols * finest, rh = grid.rows * finest;
  rasterizeLeaves(leaves, grid, rw, rh, adj.raster);
  collectEdges(adj.raster, rw, rh, adj.edges);
  edgesToCsr(leaves.size(), adj);
}

}  // namespace gmc::detail
