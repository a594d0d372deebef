#pragma once
// GMC: grid-based motion clustering (Zhang, Hasith, Wang). Pure core: no I/O.
// See doc/gmc.md for how each part maps onto the paper's equations and algorithms.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gmc/gmc/types.h"

namespace gmc {

/// One feature correspondence between the reference and the current frame.
struct MotionMatch {
  Eigen::Vector2f pixel;      ///< keypoint in the current image (px)
  Eigen::Vector3d point_ref;  ///< 3-D point in the reference camera frame (m)
  Eigen::Vector3d point_cur;  ///< 3-D point in the current camera frame (m)
};

enum class MotionLabel : std::uint8_t { Static = 0, Dynamic = 1, Undecided = 2 };

/// Parameters, named after the paper's symbols; INI section [GMC]. See doc/gmc.md.
struct GmcParams {
  bool enabled = true;         ///< false: every valid match is labelled Static (GMC off)
  int grid_cols = 20;          ///< G_x
  int grid_rows = 15;          ///< G_y
  double min_matches_per_cell = 4.0;  ///< coarsen the grid below this mean density (0 = fixed)
  double alpha = 100.0;        ///< Eq. (3): e = alpha * r / z (r in m, z = depth in m)
  double z_depth_power = 2.0;  ///< e_z = alpha * r_z / z^power (Kinect depth noise ~ z^2)
  double e_int_x = 1.0;        ///< pattern interval along x (units of e)
  double e_int_z = 1.0;        ///< pattern interval along z (units of e)
  bool use_y = false;          ///< third pattern axis (vertical motion)
  double e_int_y = 1.0;        ///< pattern interval along y when use_y
  double p_min = 0.6;          ///< quadtree: split while winner < p_min * n_i ...
  int n_min = 8;               ///< ... and n_i > n_min
  int max_depth = 2;           ///< quadtree levels below a grid cell
  int min_cell_points = 3;     ///< leaves with fewer points do not vote
  int min_cluster_size = 10;   ///< clusters with fewer features are dropped (Alg. 2)
  double merge_tolerance = 0.75;  ///< leaves join a cluster within this many intervals
  double static_tolerance = 1.0;  ///< clusters within this many intervals of zero are static
  int max_rounds = 4;          ///< shifted-binning rounds until the assignment is stable

  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "false = label every valid match static (GMC off)");
    v("grid_cols", grid_cols, 1, 200, "G_x, grid cells across the image");
    v("grid_rows", grid_rows, 1, 200, "G_y, grid cells down the image");
    v("min_matches_per_cell", min_matches_per_cell, 0.0, 1000.0,
      "coarsen the grid until cells hold this many matches on average (0 = fixed grid)");
    v("alpha", alpha, 1e-6, 1e6, "Eq. (3) scale: e = alpha * residual / depth");
    v("z_depth_power", z_depth_power, 0.0, 3.0, "depth normalisation power of the z residual");
    v("e_int_x", e_int_x, 1e-6, 1e6, "motion-pattern interval along x");
    v("e_int_z", e_int_z, 1e-6, 1e6, "motion-pattern interval along z");
    v("use_y", use_y, "add the vertical axis to the pattern table");
    v("e_int_y", e_int_y, 1e-6, 1e6, "motion-pattern interval along y (use_y)");
    v("p_min", p_min, 0.0, 1.0, "quadtree split while the winning pattern holds < p_min*n_i");
    v("n_min", n_min, 1, 100000, "quadtree split only while n_i > n_min");
    v("max_depth", max_depth, 0, 6, "quadtree levels below a grid cell");
    v("min_cell_points", min_cell_points, 1, 100000, "leaves with fewer points do not vote");
    v("min_cluster_size", min_cluster_size, 1, 100000, "clusters with fewer features are dropped");
    v("merge_tolerance", merge_tolerance, 0.01, 10.0,
      "a leaf joins an adjacent cluster whose motion is within this many intervals");
    v("static_tolerance", static_tolerance, 0.01, 10.0,
      "clusters whose mean motion is within this many intervals of zero are background");
    v("max_rounds", max_rounds, 1, 100, "shifted-binning rounds until stable");
  }
};

/// A leaf cell of the (quadtree-refined) grid.
struct GmcCell {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< pixel bounds [x0,x1) x [y0,y1)
  int depth = 0;                       ///< quadtree level, 0 = grid cell
  int num_points = 0;                  ///< n_i
  int pattern_x = 0, pattern_y = 0, pattern_z = 0;  ///< winning pattern (0,0,0 = static)
  int binning = 0;                     ///< 0 = base table, 1 = x shifted, 2 = z shifted, 3 = both
  int winner_count = 0, second_count = 0;
  Eigen::Vector3f motion = Eigen::Vector3f::Zero();  ///< mean e of the winner's members, in intervals
  int cluster = -1;                    ///< index into GmcResult::clusters, -1 = none
};

/// A merged motion cluster.
struct GmcCluster {
  int support = 0;                     ///< matches in the winning patterns of its leaves
  Eigen::Vector3d mean_residual = Eigen::Vector3d::Zero();  ///< mean e, in pattern intervals
  Eigen::Vector3d mean_motion = Eigen::Vector3d::Zero();    ///< mean 3-D residual (m)
  bool is_static = false;
};

struct GmcResult {
  std::vector<MotionLabel> labels;     ///< one per input match
  std::vector<GmcCell> cells;          ///< leaf cells
  std::vector<GmcCluster> clusters;
  int static_cluster = -1;             ///< index of the background cluster, -1 if none
  bool static_fallback = false;        ///< no cluster near zero motion: largest taken
  int iterations = 0;                  ///< re-assignment rounds until convergence
  int grid_cols = 0, grid_rows = 0;    ///< grid actually used (coarsened when sparse)
  int num_static = 0, num_dynamic = 0, num_undecided = 0;
};

/// Grid-based motion clustering. Keeps its buffers between calls (no allocation
/// in steady state); not thread-safe, use one per thread: a copy has its own buffers.
class GmcClassifier {
 public:
  explicit GmcClassifier(const GmcParams& params = {});
  ~GmcClassifier();
  GmcClassifier(const GmcClassifier& other);  ///< same parameters, new buffers
  GmcClassifier& operator=(const GmcClassifier& other);
  GmcClassifier(GmcClassifier&&) noexcept;
  GmcClassifier& operator=(GmcClassifier&&) noexcept;
  const GmcParams& params() const { return params_; }

  /// T_ref_cur: initial guess of the camera motion, mapping current-frame points into
  /// the reference frame (the paper's R_j, T_j). Matches with non-finite or
  /// non-positive depth are labelled Undecided and otherwise ignored.
  GmcResult classify(const std::vector<MotionMatch>& matches, const Isometry& T_ref_cur,
                     int image_width, int image_height);
  /// The same, writing into `out` and reusing its vectors (no allocation once they and
  /// the internal buffers have grown to the frame's size).
  void classify(const std::vector<MotionMatch>& matches, const Isometry& T_ref_cur,
                int image_width, int image_height, GmcResult& out);

 private:
  GmcParams params_;
  // implementation state lives here (buffers reused across frames), one per instance
  struct Workspace;
  std::unique_ptr<Workspace> ws_;
};

}  // namespace gmc
