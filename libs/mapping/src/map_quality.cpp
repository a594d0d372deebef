#include "gmc/mapping/map_quality.h"

#include <sstream>

namespace gmc::mapping {

GroundTruthVoxels::GroundTruthVoxels(double resolution, double max_range, int pixel_step)
    : grid_(resolution), max_range_(max_range), step_(pixel_step) {}

void GroundTruthVoxels::addFrame(const datasets::RgbdFrame& frame, const cv::Mat& mask,
                                 const Isometry& T_world_camera) {
  for (int v = step_ / 2; v < frame.depth.rows; v += step_)
    for (int u = step_ / 2; u < frame.depth.cols; u += step_) {
      const std::uint16_t raw = frame.depth.at<std::uint16_t>(v, u);
      const double z = raw * frame.depth_units;
      if (raw == 0 || z > max_range_) continue;
      const Eigen::Vector3d p = T_world_camera * frame.camera.unproject(u, v, z);
      octomap::OcTreeKey key;
      if (!grid_.coordToKeyChecked(octomap::point3d(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                                    static_cast<float>(p.z())),
                                   key))
        continue;
      (mask.at<std::uint8_t>(v, u) ? dynamic_ : static_).insert(key);
    }
}

MapQuality GroundTruthVoxels::evaluate(const octomap::OcTree& map) const {
  MapQuality q;
  auto occupied = [&](const octomap::OcTreeKey& k) {
    const auto* node = map.search(k);
    return node && map.isNodeOccupied(node);
  };
  for (const auto& k : dynamic_) {
    if (static_.count(k)) continue;
    ++q.dynamic_only_voxels;
    q.ghost_voxels += occupied(k);
  }
  for (const auto& k : static_) {
    ++q.static_voxels_seen;
    q.static_voxels_occupied += occupied(k);
  }
  return q;
}

std::string toJson(const MapQuality& q) {
  std::ostringstream os;
  os << "{\"ghost_voxels\": " << q.ghost_voxels << ", \"dynamic_only_voxels\": " << q.dynamic_only_voxels
     << ", \"static_voxels_seen\": " << q.static_voxels_seen
     << ", \"static_voxels_occupied\": " << q.static_voxels_occupied
     << ", \"static_coverage\": " << q.static_coverage() << "}";
  return os.str();
}

}  // namespace gmc::mapping
