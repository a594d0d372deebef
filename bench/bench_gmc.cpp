// GMC and GMS on synthetic correspondences (tests/gmc/synthetic_matches.h): a static
// background plus two walkers, realistic keypoint and Kinect depth noise.
#include <benchmark/benchmark.h>

#include "synthetic_matches.h"

namespace {

gmc::synth::Generated scene(int n) {
  gmc::synth::Scenario s;
  s.num_matches = n;
  s.seed = 99;
  s.T_ref_cur = gmc::synth::cameraMotion(0.01, -0.003, 0.008, 0.3);
  s.movers = {{100, 80, 228, 430, 1.8, Eigen::Vector3d(1.0, 0, 0.2)},
              {380, 60, 520, 440, 2.6, Eigen::Vector3d(-0.8, 0, 0.5)}};
  return gmc::synth::generate(s);
}

void BM_GmcClassify(benchmark::State& state) {
  const auto g = scene(static_cast<int>(state.range(0)));
  const auto T = gmc::synth::cameraMotion(0.01, -0.003, 0.008, 0.3);
  gmc::GmcClassifier gmc;
  gmc::GmcResult r;  // reused, as the odometry does: steady state allocates nothing
  for (auto _ : state) {
    gmc.classify(g.matches, T, 640, 480, r);
    benchmark::DoNotOptimize(r);
  }
  state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_GmcClassify)->Arg(500)->Arg(1000)->Arg(2000)->Arg(5000)->Unit(benchmark::kMicrosecond)->Complexity(benchmark::oN);

void BM_Gms(benchmark::State& state) {
  const auto c = gmc::synth::makeGmsCase(static_cast<int>(state.range(0)) / 2, 0.5, 3);
  for (auto _ : state) {
    auto keep = gmc::gmsFilter(c.kp1, 640, 480, c.kp2, 640, 480, c.matches);
    benchmark::DoNotOptimize(keep);
  }
  state.SetComplexityN(state.range(0));
}
BENCHMARK(BM_Gms)->Arg(500)->Arg(1000)->Arg(2000)->Arg(5000)->Unit(benchmark::kMicrosecond)->Complexity(benchmark::oN);

}  // namespace
