#pragma once
// GMS: grid-based motion statistics match filter (Bian et al., CVPR 2017).
#include <cstdint>
#include <vector>

namespace gmc {

struct GmsKeypoint {
  float x = 0, y = 0;
  float size = 0;   ///< used by the scale variant
  float angle = 0;  ///< degrees, used by the rotation variant
};

struct GmsMatch {
  int query = 0;  ///< index into the first keypoint list
  int train = 0;  ///< index into the second keypoint list
};

/// INI section [GMS].
struct GmsParams {
  int grid_cols = 20;
  int grid_rows = 20;
  double alpha = 6.0;          ///< threshold alpha*sqrt(n)
  double min_matches_per_cell = 25.0;  ///< coarsen the grid below this density (0 = fixed grid)
  bool with_scale = false;
  bool with_rotation = false;

  template <class V>
  void visit(V& v) {
    v("grid_cols", grid_cols, 1, 200, "GMS grid cells across each image");
    v("grid_rows", grid_rows, 1, 200, "GMS grid cells down each image");
    v("alpha", alpha, 0.0, 100.0, "inlier threshold alpha*sqrt(mean features per cell)");
    v("min_matches_per_cell", min_matches_per_cell, 0.0, 1000.0,
      "coarsen the grid until cells hold this many matches on average (0 = fixed grid)");
    v("with_scale", with_scale, "also try 5 relative scales");
    v("with_rotation", with_rotation, "also try 8 relative rotations");
  }
};

/// Returns one flag per match: 1 = kept (inlier), 0 = rejected.
std::vector<std::uint8_t> gmsFilter(const std::vector<GmsKeypoint>& keypoints1, int width1,
                                    int height1, const std::vector<GmsKeypoint>& keypoints2,
                                    int width2, int height2, const std::vector<GmsMatch>& matches,
                                    const GmsParams& params = {});

}  // namespace gmc
