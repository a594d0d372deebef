// GMC: grid-based motion clustering. classify() is the recipe of Algorithm 1
// (assignment) and Algorithm 2 (merge) of the paper, one named step per section
// (classify_steps.h); doc/gmc.md explains each decision.
#include "gmc/gmc/gmc.h"

#include "classify_steps.h"

namespace gmc {

using namespace detail;

struct GmcClassifier::Workspace : ClassifyWorkspace {};

GmcClassifier::GmcClassifier(const GmcParams& params)
    : params_(params), ws_(std::make_unique<Workspace>()) {}
GmcClassifier::~GmcClassifier() = default;
GmcClassifier::GmcClassifier(GmcClassifier&&) noexcept = default;
GmcClassifier& GmcClassifier::operator=(GmcClassifier&&) noexcept = default;
// A copy gets its own buffers: copies are meant for other threads.
GmcClassifier::GmcClassifier(const GmcClassifier& other)
    : params_(other.params_), ws_(std::make_unique<Workspace>()) {}
GmcClassifier& GmcClassifier::operator=(const GmcClassifier& other) {
  if (this != &other) {
    params_ = other.params_;
    if (!ws_) ws_ = std::make_unique<Workspace>();
  }
  return *this;
}

namespace {

/// Every field reset, the vectors' capacity kept.
void resetResult(size_t num_matches, GmcResult& result) {
  result.labels.assign(num_matches, MotionLabel::Undecided);
  result.cells.clear();
  result.clusters.clear();
  result.static_cluster = -1;
  result.static_fallback = false;
  result.iterations = 0;
  result.grid_cols = result.grid_rows = 0;
  result.num_static = result.num_dynamic = result.num_undecided = 0;
}

/// GMC off: every usable match is static.
void labelAllStatic(const Residuals& res, GmcResult& result) {
  for (size_t i = 0; i < res.valid.size(); ++i)
    if (res.valid[i]) result.labels[i] = MotionLabel::Static;
  result.num_static = res.num_valid;
  result.num_undecided = static_cast<int>(res.valid.size()) - res.num_valid;
}

/// Leaves point at the kept clusters' new indices (-1 for dropped ones).
void remapLeafClusters(const std::vector<int>& remap, std::vector<Leaf>& leaves) {
  for (auto& leaf : leaves) leaf.cluster = leaf.cluster >= 0 ? remap[static_cast<size_t>(leaf.cluster)] : -1;
}

}  // namespace

GmcResult GmcClassifier::classify(const std::vector<MotionMatch>& matches, const Isometry& T_ref_cur,
                                  int image_width, int image_height) {
  GmcResult result;
  classify(matches, T_ref_cur, image_width, image_height, result);
  return result;
}

// The recipe of Section 3; each step is in classify_steps.h.
void GmcClassifier::classify(const std::vector<MotionMatch>& matches, const Isometry& T_ref_cur,
                             int image_width, int image_height, GmcResult& result) {
  resetResult(matches.size(), result);
  if (matches.empty() || image_width <= 0 || image_height <= 0) return;
  Workspace& w = *ws_;
  const GmcParams& p = params_;
  const float merge_tol = static_cast<float>(p.merge_tolerance);

  computeResiduals(matches, T_ref_cur, image_width, image_height, p, w.residuals);  // Eq. (3)
  if (!p.enabled) return labelAllStatic(w.residuals, result);
  const Grid grid = chooseGrid(p, w.residuals.num_valid, image_width, image_height);
  result.grid_cols = grid.cols;
  result.grid_rows = grid.rows;
  bucketByCell(matches, w.residuals, grid, w.buckets);                              // grid tensor
  splitQuadtree(matches, w.residuals, grid, p, w.buckets, w.leaves, w.quadtree);   // pattern tables
  leafMotions(w.residuals, w.buckets.items, p.min_cell_points, w.leaves);
  buildAdjacency(w.leaves, grid, p.max_depth, w.adjacency);
  mergeWithNms(w.leaves, w.adjacency, merge_tol, w.merge);                          // Alg. 2
  result.iterations = reassignUntilStable(w.leaves, w.adjacency, merge_tol, p.max_rounds, w.merge);
  chooseBackground(w.merge.acc, p, w.remap, result);
  remapLeafClusters(w.remap, w.leaves);
  labelMatches(matches, T_ref_cur, w.residuals, w.buckets.items, w.leaves, w.adjacency, w.labels, result);
  writeCells(w.leaves, result);
  countLabels(result);
}

}  // namespace gmc
