#include "gmc/mapping/map_quality.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace gmc::mapping {

GroundTruthVoxels::GroundTruthVoxels(double resolution, double max_range, int pixel_step, double min_range)
    : grid_(resolution), min_range_(min_range), max_range_(max_range), step_(pixel_step) {}

GroundTruthVoxels::GroundTruthVoxels(const StaticMapOptions& o)
    : GroundTruthVoxels(o.resolution, o.max_range, o.pixel_step, o.min_range) {}

void GroundTruthVoxels::addFrame(const datasets::RgbdFrame& frame, const cv::Mat& mask,
                                 const Isometry& T_world_camera) {
  if (frame.depth.type() != CV_16UC1 || mask.type() != CV_8UC1 || mask.size() != frame.depth.size())
    throw std::invalid_argument(frame.name + ": ground truth needs CV_16UC1 depth and a CV_8UC1 mask of its size");
  for (int v = step_ / 2; v < frame.depth.rows; v += step_)
    for (int u = step_ / 2; u < frame.depth.cols; u += step_) {
      const std::uint16_t raw = frame.depth.at<std::uint16_t>(v, u);
      const double z = raw * frame.depth_units;
      if (raw == 0 || z < min_range_ || z > max_range_) continue;
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
  return mapping::evaluate(map, *this);
}

MapQuality evaluate(const octomap::OcTree& map, const GroundTruthVoxels& truth) {
  if (std::abs(map.getResolution() - truth.resolution()) > 1e-9)
    throw std::invalid_argument("map resolution " + std::to_string(map.getResolution()) +
                                " differs from the ground truth's " + std::to_string(truth.resolution()));
  MapQuality q;
  auto occupied = [&](const octomap::OcTreeKey& k) {
    const auto* node = map.search(k);
    return node && map.isNodeOccupied(node);
  };
  for (const auto& k : truth.dynamicKeys()) {
    if (truth.staticKeys().count(k)) continue;
    ++q.dynamic_only_voxels;
    q.ghost_voxels += occupied(k);
  }
  for (const auto& k : truth.staticKeys()) {
    ++q.static_voxels_seen;
    q.static_voxels_occupied += occupied(k);
  }
  return q;
}

std::string toJson(const MapQuality& q) {
  const nlohmann::ordered_json j = {{"ghost_voxels", q.ghost_voxels},
                                    {"dynamic_only_voxels", q.dynamic_only_voxels},
                                    {"static_voxels_seen", q.static_voxels_seen},
                                    {"static_voxels_occupied", q.static_voxels_occupied},
                                    {"static_coverage", q.static_coverage()}};
  return j.dump();
}

}  // namespace gmc::mapping
