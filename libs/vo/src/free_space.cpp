#include "gmc/vo/free_space.h"

#include <algorithm>
#include <cstdint>

namespace gmc::vo {

void FreeSpaceHistory::push(const cv::Mat& depth, double depth_units, const Isometry& T_world_camera,
                            double stamp) {
  if (!options_.enabled || (!views_.empty() && stamp - views_.back().stamp < options_.spacing_seconds)) return;
  while (!views_.empty() && stamp - views_.front().stamp > options_.history_seconds) views_.pop_front();
  const int c = options_.cell_px;
  View v;
  v.stamp = stamp;
  v.T_camera_world = T_world_camera.inverse();
  v.nearest = cv::Mat1f::zeros(depth.rows / c, depth.cols / c);
  for (int y = 0; y < v.nearest.rows * c; ++y) {
    const auto* row = depth.ptr<std::uint16_t>(y);
    float* cells = v.nearest.ptr<float>(y / c);
    for (int x = 0; x < v.nearest.cols * c; ++x) {
      if (row[x] == 0) continue;
      float& cell = cells[x / c];
      const float z = static_cast<float>(row[x] * depth_units);
      if (cell == 0 || z < cell) cell = z;
    }
  }
  views_.push_back(std::move(v));
}

int FreeSpaceHistory::seenThrough(const Eigen::Vector3d& p_world, const PinholeCamera& camera, double before) const {
  int count = 0;
  const double c = options_.cell_px;
  for (const View& v : views_) {
    if (v.stamp > before) break;
    const Eigen::Vector3d p = v.T_camera_world * p_world;
    if (p.z() <= 0.1) continue;
    const Eigen::Vector2d uv = camera.project(p);
    const int cu = static_cast<int>(uv.x() / c), cv_ = static_cast<int>(uv.y() / c);
    if (cu < 1 || cv_ < 1 || cu + 1 >= v.nearest.cols || cv_ + 1 >= v.nearest.rows) continue;
    // The nearest reading around the pixel (a cell either side: pose error and depth
    // edges) must be beyond the point; a cell without reading decides nothing.
    float nearest = 1e9f;
    bool unknown = false;
    for (int dy = -1; dy <= 1 && !unknown; ++dy)
      for (int dx = -1; dx <= 1 && !unknown; ++dx) {
        const float z = v.nearest(cv_ + dy, cu + dx);
        unknown = z == 0;
        nearest = std::min(nearest, z);
      }
    if (unknown) continue;
    const double margin = options_.margin_base + options_.margin_per_m2 * p.z() * p.z();
    if (nearest > p.z() + margin) ++count;
  }
  return count;
}

}  // namespace gmc::vo
