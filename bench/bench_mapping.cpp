// Static-map insertion cost (gmc::mapping::StaticMapBuilder) on the frames of a gmc-sim
// sequence, and ghost voxels / static coverage against its ground truth for a few
// probability settings, with the exact mask and with none.
//   GMC_SIM_SEQ=/path/to/gmc-sim/folder  bin/mapping_benchmarks
// Without GMC_SIM_SEQ the benchmarks skip with a message.
#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

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

bool haveSequence(benchmark::State& state) {
  if (!sequence().empty()) return true;
  state.SkipWithError("set GMC_SIM_SEQ to a gmc-sim folder (e.g. walkers_xyz)");
  return false;
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
