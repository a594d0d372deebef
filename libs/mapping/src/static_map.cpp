#include "gmc/mapping/static_map.h"

#include <sstream>
#include <stdexcept>

#include "gmc/datasets/atomic_file.h"

namespace gmc::mapping {

StaticMapBuilder::StaticMapBuilder(const StaticMapOptions& options)
    : options_(options), tree_(std::make_unique<octomap::OcTree>(options.resolution)) {
  tree_->setProbHit(options.prob_hit);
  tree_->setProbMiss(options.prob_miss);
  tree_->setClampingThresMin(options.clamp_min);
  tree_->setClampingThresMax(options.clamp_max);
}

void StaticMapBuilder::insertFrame(const datasets::RgbdFrame& frame, const cv::Mat& dynamic_mask,
                                   const Isometry& T_world_camera) {
  const auto& cam = frame.camera;
  const Eigen::Vector3d origin = T_world_camera.translation();
  const octomap::point3d o(static_cast<float>(origin.x()), static_cast<float>(origin.y()),
                           static_cast<float>(origin.z()));
  cloud_.clear();
  octomap::KeySet free_keys;
  octomap::KeyRay ray;
  const int step = options_.pixel_step;
  for (int v = step / 2; v < frame.depth.rows; v += step) {
    const auto* drow = frame.depth.ptr<std::uint16_t>(v);
    const auto* mrow = dynamic_mask.empty() || !options_.use_dynamic_mask ? nullptr : dynamic_mask.ptr<std::uint8_t>(v);
    for (int u = step / 2; u < frame.depth.cols; u += step) {
      const double z = drow[u] * frame.depth_units;
      if (drow[u] == 0 || z < options_.min_range) continue;
      const Eigen::Vector3d p = T_world_camera * cam.unproject(u, v, z);
      if (mrow && mrow[u]) {
        if (!options_.clear_dynamic_rays) continue;
        // Free space up to just before the walker: the ray proves it empty.
        const double len = (p - origin).norm();
        const double keep = std::min(len, options_.max_range) - options_.dynamic_ray_margin;
        if (keep <= 0) continue;
        const Eigen::Vector3d end = origin + (p - origin) * (keep / len);
        if (tree_->computeRayKeys(o, octomap::point3d(static_cast<float>(end.x()), static_cast<float>(end.y()),
                                                      static_cast<float>(end.z())),
                                  ray))
          free_keys.insert(ray.begin(), ray.end());
        continue;
      }
      cloud_.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    }
  }
  tree_->insertPointCloud(cloud_, o, options_.max_range, false, options_.discretize);
  for (const auto& key : free_keys) tree_->updateNode(key, false, false);
  ++frames_;
}

MapStats StaticMapBuilder::stats() const {
  MapStats s;
  s.frames_inserted = frames_;
  s.memory_bytes = tree_->memoryUsage();
  bool first = true;
  for (auto it = tree_->begin_leafs(); it != tree_->end_leafs(); ++it) {
    ++s.leaf_nodes;
    if (!tree_->isNodeOccupied(*it)) {
      ++s.free_leaves;
      continue;
    }
    ++s.occupied_leaves;
    const double size = it.getSize();
    s.occupied_volume_m3 += size * size * size;
    const Eigen::Vector3d c(it.getX(), it.getY(), it.getZ());
    s.min = first ? c : s.min.cwiseMin(c);
    s.max = first ? c : s.max.cwiseMax(c);
    first = false;
  }
  return s;
}

void StaticMapBuilder::writeBinary(const std::string& path) const {
  datasets::AtomicFile file(path);
  if (!tree_->writeBinary(file.tempPath())) throw std::runtime_error(path + ": cannot write map");
  file.commit();
}

std::string toJson(const MapStats& s) {
  std::ostringstream os;
  os.precision(6);
  os << "{\"frames_inserted\": " << s.frames_inserted << ", \"leaf_nodes\": " << s.leaf_nodes
     << ", \"occupied_leaves\": " << s.occupied_leaves << ", \"free_leaves\": " << s.free_leaves
     << ", \"memory_bytes\": " << s.memory_bytes << ", \"occupied_volume_m3\": "
     << s.occupied_volume_m3 << ", \"bbox_min\": [" << s.min.x() << ", " << s.min.y() << ", "
     << s.min.z() << "], \"bbox_max\": [" << s.max.x() << ", " << s.max.y() << ", " << s.max.z()
     << "]}";
  return os.str();
}

std::string toText(const MapStats& s) {
  std::ostringstream os;
  os.precision(4);
  os << s.occupied_leaves << " occupied / " << s.leaf_nodes << " leaves, "
     << s.memory_bytes / 1024 << " KiB, " << s.frames_inserted << " frames inserted";
  return os.str();
}

}  // namespace gmc::mapping
