#include "gmc/mapping/static_map.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include <sstream>
#include <stdexcept>
#include <vector>

#include "gmc/datasets/atomic_file.h"
#include "gmc/gmc/options.h"

namespace gmc::mapping {

namespace {

octomap::point3d toOcto(const Eigen::Vector3d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
}

}  // namespace

StaticMapBuilder::StaticMapBuilder(const StaticMapOptions& options) : options_(options) {
  if (const std::string error = validateOptions(options_, "Mapping"); !error.empty())
    throw std::invalid_argument(error);
  tree_ = std::make_unique<octomap::OcTree>(options.resolution);
  tree_->setProbHit(options.prob_hit);
  tree_->setProbMiss(options.prob_miss);
  tree_->setClampingThresMin(options.clamp_min);
  tree_->setClampingThresMax(options.clamp_max);
  if (options.mask_dilate_px > 0)
    kernel_ = cv::getStructuringElement(cv::MORPH_ELLIPSE,
                                        cv::Size(2 * options.mask_dilate_px + 1, 2 * options.mask_dilate_px + 1));
}

bool StaticMapBuilder::insertFrame(const datasets::RgbdFrame& frame, const cv::Mat& dynamic_mask,
                                   const Isometry& T_world_camera) {
  if (frames_offered_++ % static_cast<size_t>(options_.insert_every_n_frames) != 0) return false;
  if (frame.depth.type() != CV_16UC1)
    throw std::invalid_argument(frame.name + ": map insertion needs CV_16UC1 depth");
  const bool masked = options_.use_dynamic_mask && !dynamic_mask.empty();
  if (masked && (dynamic_mask.type() != CV_8UC1 || dynamic_mask.size() != frame.depth.size()))
    throw std::invalid_argument(frame.name + ": dynamic mask must be CV_8UC1 of the depth's size");
  const cv::Mat* mask = nullptr;
  if (masked) {
    if (kernel_.empty()) {
      mask = &dynamic_mask;
    } else {
      cv::dilate(dynamic_mask, dilated_mask_, kernel_);
      mask = &dilated_mask_;
    }
  }
  sampleEndpoints(frame, mask, T_world_camera);
  const octomap::point3d o = toOcto(T_world_camera.translation());
  // The update insertPointCloud() would make, plus the free space in front of people;
  // a voxel holding a static endpoint of this frame is never cleared by it.
  free_keys_.clear();
  occupied_keys_.clear();
  if (options_.discretize)
    tree_->computeDiscreteUpdate(cloud_, o, free_keys_, occupied_keys_, options_.max_range);
  else
    tree_->computeUpdate(cloud_, o, free_keys_, occupied_keys_, options_.max_range);
  addDynamicRays(o);
  for (const auto& key : free_keys_) tree_->updateNode(key, false);
  for (const auto& key : occupied_keys_) tree_->updateNode(key, true);
  ++frames_;
  return true;
}

/// cloud_: static endpoints; dynamic_ends_: where the rays to dynamic pixels stop (the
/// ray proves the space up to just before the person empty).
void StaticMapBuilder::sampleEndpoints(const datasets::RgbdFrame& frame, const cv::Mat* mask,
                                       const Isometry& T_world_camera) {
  const Eigen::Vector3d origin = T_world_camera.translation();
  cloud_.clear();
  dynamic_ends_.clear();
  const int step = options_.pixel_step;
  for (int v = step / 2; v < frame.depth.rows; v += step) {
    const auto* drow = frame.depth.ptr<std::uint16_t>(v);
    const auto* mrow = mask ? mask->ptr<std::uint8_t>(v) : nullptr;
    for (int u = step / 2; u < frame.depth.cols; u += step) {
      const double z = drow[u] * frame.depth_units;
      if (drow[u] == 0 || z < options_.min_range) continue;
      const Eigen::Vector3d p = T_world_camera * frame.camera.unproject(u, v, z);
      if (!mrow || !mrow[u]) {
        cloud_.push_back(toOcto(p));
        continue;
      }
      if (!options_.clear_dynamic_rays) continue;
      const double len = (p - origin).norm();
      const double keep = std::min(len, options_.max_range) - options_.dynamic_ray_margin;
      if (keep > 0) dynamic_ends_.push_back(origin + (p - origin) * (keep / len));
    }
  }
}

/// Free keys along the rays to dynamic_ends_, except this frame's occupied voxels. With
/// `discretize`, one ray per end voxel (to its centre), as OctoMap's discretized update
/// does for the static endpoints: neighbouring pixels on a person share most voxels.
void StaticMapBuilder::addDynamicRays(const octomap::point3d& origin) {
  auto addRay = [&](const octomap::point3d& end) {
    if (!tree_->computeRayKeys(origin, end, ray_)) return;
    for (const auto& key : ray_)
      if (!occupied_keys_.count(key)) free_keys_.insert(key);
  };
  if (!options_.discretize) {
    for (const Eigen::Vector3d& p : dynamic_ends_) addRay(toOcto(p));
    return;
  }
  dynamic_keys_.clear();
  octomap::OcTreeKey key;
  for (const Eigen::Vector3d& p : dynamic_ends_)
    if (tree_->coordToKeyChecked(toOcto(p), key)) dynamic_keys_.insert(key);
  for (const auto& k : dynamic_keys_) addRay(tree_->keyToCoord(k));
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
  const nlohmann::ordered_json j = {{"frames_inserted", s.frames_inserted},
                                    {"leaf_nodes", s.leaf_nodes},
                                    {"occupied_leaves", s.occupied_leaves},
                                    {"free_leaves", s.free_leaves},
                                    {"memory_bytes", s.memory_bytes},
                                    {"occupied_volume_m3", s.occupied_volume_m3},
                                    {"bbox_min", {s.min.x(), s.min.y(), s.min.z()}},
                                    {"bbox_max", {s.max.x(), s.max.y(), s.max.z()}}};
  return j.dump();
}

std::string toText(const MapStats& s) {
  std::ostringstream os;
  os.precision(4);
  os << s.occupied_leaves << " occupied / " << s.leaf_nodes << " leaves, "
     << s.memory_bytes / 1024 << " KiB, " << s.frames_inserted << " frames inserted";
  return os.str();
}

}  // namespace gmc::mapping
