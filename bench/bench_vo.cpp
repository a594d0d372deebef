// The odometry's start consensus (a new map's first frames judged together): one judgement
// over F kept frames of 300 matched landmarks, 200 samples as configured by default. It runs
// on a map's first `frames` (12) frames only, on top of that frame's odometry.
#include <benchmark/benchmark.h>

#include <random>

#include "gmc/vo/start_consensus.h"

namespace {

void BM_StartConsensusSolve(benchmark::State& state) {
  const int frames = static_cast<int>(state.range(0));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(-1.5, 1.5), y(-1.0, 1.0), z(2.0, 4.0), jitter(-0.01, 0.01);
  std::vector<std::pair<int, Eigen::Vector3d>> anchors;
  for (int i = 0; i < 300; ++i) anchors.emplace_back(i, Eigen::Vector3d(x(rng), y(rng), z(rng)));
  gmc::vo::StartConsensus consensus;
  consensus.start(anchors);
  for (int f = 1; f <= frames; ++f) {
    gmc::vo::ConsensusFrame frame;
    frame.frame_number = f;
    frame.stamp = f / 30.0;
    // Two thirds of the landmarks are walkers drifting 2 cm a frame with 1 cm of swing.
    for (const auto& [id, p] : anchors) {
      const Eigen::Vector3d moved = id % 3 == 0 ? p : Eigen::Vector3d(p + Eigen::Vector3d(0.02 * f + jitter(rng), jitter(rng), 0));
      frame.observations.emplace_back(id, moved - Eigen::Vector3d(0.003 * f, 0, 0));
    }
    consensus.add(frame);
  }
  for (auto _ : state) benchmark::DoNotOptimize(consensus.solve(gmc::vo::InPlaceThreshold{}));
}
BENCHMARK(BM_StartConsensusSolve)->Arg(4)->Arg(8)->Arg(12)->Unit(benchmark::kMillisecond);

}  // namespace
