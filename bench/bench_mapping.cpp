// Static-map insertion cost (gmc::mapping::StaticMapBuilder) on the frames of a gmc-sim
// sequence, and ghost voxels / static coverage against its ground truth for a few
// probability settings, with the exact mask and with none.
//   GMC_SIM_SEQ=/path/to/gmc-sim/folder  bin/mapping_benchmarks
// Without GMC_SIM_SEQ the benchmarks skip with a message.
// BM_Bonn*: insertions per second on the real Bonn crowd window (GMC_DATA_DIR, default
// ../shared/data; skip with a message when absent): OctoMap's own insertPointCloud
// variants next to the builder, on the same clouds in the same run.
#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_data.h"
#include "gmc/datasets/camera.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "gmc/mapping/map_quality.h"
#include "gmc/mapping/static_map.h"

namespace {

using namespace gmc;

struct GtFrame {
  datasets::RgbdFrame frame;
  cv::Mat mask;  // the simulator's exact person mask
  Isometry T_world_camera;
};

/// Every `stride`-th of the first frames of $GMC_SIM_SEQ (empty when unset or unreadable).
const std::vector<GtFrame>& sequence() {
  static const std::vector<GtFrame> frames = [] {
    std::vector<GtFrame> out;
    const char* dir = std::getenv("GMC_SIM_SEQ");
    if (!dir) return out;
    const auto gt = datasets::readTumTrajectory(std::string(dir) + "/groundtruth.txt");
    auto source = datasets::openRgbdSource(dir, PinholeCamera{});
    datasets::RgbdFrame f;
    for (int i = 0; source->next(f) && out.size() < 150; ++i) {
      if (i % 2) continue;
      char name[64];
      std::snprintf(name, sizeof name, "/masks/%.6f.png", f.stamp);
      const auto pose = datasets::interpolatePose(gt, f.stamp);
      cv::Mat mask = cv::imread(std::string(dir) + name, cv::IMREAD_GRAYSCALE);
      if (!pose || mask.empty()) continue;
      GtFrame g{f, mask, *pose};
      g.frame.rgb = f.rgb.clone();  // the source may reuse its buffers
      g.frame.depth = f.depth.clone();
      out.push_back(std::move(g));
    }
    return out;
  }();
  return frames;
}

/// False (the benchmark skipped, saying why) when its frames are missing.
bool haveFrames(benchmark::State& state, bool have, const char* why) {
  if (!have) state.SkipWithError(why);
  return have;
}

bool haveSequence(benchmark::State& state) {
  return haveFrames(state, !sequence().empty(), "set GMC_SIM_SEQ to a gmc-sim folder (e.g. walkers_xyz)");
}

/// ms per inserted frame with the exact masks; args: pixel_step, discretize.
void BM_InsertFrame(benchmark::State& state) {
  if (!haveSequence(state)) return;
  mapping::StaticMapOptions o;
  o.pixel_step = static_cast<int>(state.range(0));
  o.discretize = state.range(1) != 0;
  mapping::StaticMapBuilder map(o);
  size_t i = 0;
  for (auto _ : state) {
    const GtFrame& g = sequence()[i++ % sequence().size()];
    map.insertFrame(g.frame, g.mask, g.T_world_camera);
  }
  state.counters["rays_per_frame"] = (640.0 / o.pixel_step) * (480.0 / o.pixel_step);
  state.counters["occupied_leaves"] = static_cast<double>(map.stats().occupied_leaves);
}
BENCHMARK(BM_InsertFrame)
    ->ArgsProduct({{2, 4, 8}, {0, 1}})
    ->ArgNames({"pixel_step", "discretize"})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);

/// Ghost voxels and static coverage per (prob_miss x 100, clamp_max x 100, exact mask or
/// none): without a mask, how much the free-space rays alone clean up, and at what cost
/// in static coverage.
void BM_MapQuality(benchmark::State& state) {
  if (!haveSequence(state)) return;
  mapping::StaticMapOptions o;
  o.prob_miss = state.range(0) / 100.0;
  o.clamp_max = state.range(1) / 100.0;
  const bool use_mask = state.range(2) != 0;
  mapping::MapQuality q;
  for (auto _ : state) {
    mapping::StaticMapBuilder map(o);
    mapping::GroundTruthVoxels truth(o.resolution, o.max_range, o.pixel_step);
    for (const GtFrame& g : sequence()) {
      map.insertFrame(g.frame, use_mask ? g.mask : cv::Mat(), g.T_world_camera);
      truth.addFrame(g.frame, g.mask, g.T_world_camera);
    }
    q = mapping::evaluate(map.tree(), truth);
  }
  state.counters["ghost_voxels"] = static_cast<double>(q.ghost_voxels);
  state.counters["dynamic_only"] = static_cast<double>(q.dynamic_only_voxels);
  state.counters["static_coverage"] = q.static_coverage();
}
BENCHMARK(BM_MapQuality)
    ->ArgsProduct({{40, 30}, {97, 90}, {0, 1}})
    ->ArgNames({"miss_pct", "clamp_max_pct", "mask"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace

namespace {

/// The published Bonn conversion from the marker body to the camera's optical frame:
/// T_ros * T_gt * T_ros * T_m (T_m's rotation projected onto the nearest rotation).
Isometry bonnCameraPose(const Isometry& T_gt) {
  Eigen::Matrix4d ros;
  ros << -1, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 1;
  Eigen::Matrix4d m;
  m << 1.0157, 0.1828, -0.2389, 0.0113, 0.0009, -0.8431, -0.6413, -0.0098, -0.3009, 0.6147, -0.8085, 0.0111, 0,
      0, 0, 1;
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(m.topLeftCorner<3, 3>(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  m.topLeftCorner<3, 3>() = svd.matrixU() * svd.matrixV().transpose();
  Isometry out;
  out.matrix() = ros * T_gt.matrix() * ros * m;
  return out;
}

struct PosedFrame {
  datasets::RgbdFrame frame;
  Isometry T_world_camera;
  octomap::Pointcloud cloud;  // the static endpoints the builder inserts (pixel_step 4)
};

/// Dynamic pixels of the bench: a vertical band over the middle third of the image, a
/// stand-in for a walker (no per-frame GMC here), so the rays-to-people path is measured.
cv::Mat bandMask(const cv::Size& size) {
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  mask.colRange(size.width / 3, 2 * size.width / 3).setTo(255);
  return mask;
}

/// The points insertFrame() would insert as occupied (same sampling, range, mask).
octomap::Pointcloud staticCloud(const datasets::RgbdFrame& f, const cv::Mat& mask, const Isometry& T,
                                const mapping::StaticMapOptions& o) {
  octomap::Pointcloud cloud;
  for (int v = o.pixel_step / 2; v < f.depth.rows; v += o.pixel_step)
    for (int u = o.pixel_step / 2; u < f.depth.cols; u += o.pixel_step) {
      const double z = f.depthAt(u, v);
      if (z == 0 || z < o.min_range || mask.at<std::uint8_t>(v, u)) continue;
      const Eigen::Vector3d p = T * f.camera.unproject(u, v, z);
      cloud.push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    }
  return cloud;
}

const std::vector<PosedFrame>& bonnFrames() {
  static const std::vector<PosedFrame> frames = [] {
    std::vector<PosedFrame> out;
    const std::string dir = gmc::bench::sharedDataFolder("bonn_crowd_240_389");
    if (dir.empty() || !std::filesystem::exists(dir + "/groundtruth.txt")) return out;
    const auto gt = datasets::readTumTrajectory(dir + "/groundtruth.txt");
    auto source = datasets::openRgbdSource(dir, datasets::cameraPreset("bonn"));
    datasets::RgbdFrame f;
    while (source->next(f)) {
      const auto pose = datasets::interpolatePose(gt, f.stamp);
      if (!pose) continue;
      const Isometry T = bonnCameraPose(*pose);
      datasets::RgbdFrame own = f;
      own.depth = f.depth.clone();  // the source may reuse its buffers
      own.rgb.release();            // not used by the map
      out.push_back({own, T, staticCloud(own, bandMask(own.depth.size()), T, {})});
    }
    return out;
  }();
  return frames;
}

bool haveBonn(benchmark::State& state) {
  return haveFrames(state, !bonnFrames().empty(), "no bonn_crowd_240_389 under GMC_DATA_DIR (default ../shared/data)");
}

void reportRate(benchmark::State& state, const octomap::OcTree& tree) {
  state.SetItemsProcessed(state.iterations());  // items/s = insertions per second
  state.counters["frames"] = static_cast<double>(bonnFrames().size());
  state.counters["tree_nodes"] = static_cast<double>(tree.size());
}

/// OctoMap's own insertPointCloud of the builder's static clouds (no rays to people);
/// args: discretize, lazy_eval (then one updateInnerOccupancy() per frame).
void BM_BonnOctomapInsertPointCloud(benchmark::State& state) {
  if (!haveBonn(state)) return;
  const mapping::StaticMapOptions o;
  octomap::OcTree tree(o.resolution);
  const bool discretize = state.range(0) != 0, lazy = state.range(1) != 0;
  size_t i = 0;
  for (auto _ : state) {
    const PosedFrame& f = bonnFrames()[i++ % bonnFrames().size()];
    const Eigen::Vector3d t = f.T_world_camera.translation();
    const octomap::point3d origin(static_cast<float>(t.x()), static_cast<float>(t.y()), static_cast<float>(t.z()));
    tree.insertPointCloud(f.cloud, origin, o.max_range, lazy, discretize);
    if (lazy) tree.updateInnerOccupancy();
  }
  reportRate(state, tree);
}
BENCHMARK(BM_BonnOctomapInsertPointCloud)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->ArgNames({"discretize", "lazy"})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(5.0);

/// The builder (static-only rule, rays to the band's "person" clear free space); args:
/// pixel_step, discretize (static and dynamic ends).
void BM_BonnBuilder(benchmark::State& state) {
  if (!haveBonn(state)) return;
  mapping::StaticMapOptions o;
  o.pixel_step = static_cast<int>(state.range(0));
  o.discretize = state.range(1) != 0;
  mapping::StaticMapBuilder map(o);
  const cv::Mat mask = bandMask(bonnFrames().front().frame.depth.size());
  size_t i = 0;
  for (auto _ : state) {
    const PosedFrame& f = bonnFrames()[i++ % bonnFrames().size()];
    map.insertFrame(f.frame, mask, f.T_world_camera);
  }
  reportRate(state, map.tree());
}
BENCHMARK(BM_BonnBuilder)
    ->ArgsProduct({{4, 8}, {0, 1}})
    ->ArgNames({"pixel_step", "discretize"})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(5.0);

}  // namespace
