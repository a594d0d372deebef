// The odometry's per-frame background selection, and its start consensus (a new map's first
// frames judged together, on a map's first `frames` (12) frames only, on top of their odometry).
#include <benchmark/benchmark.h>

#include <random>

#include "gmc/vo/background.h"
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

// One frame's background selection: N matches, 60 % on the room (the camera moved 2 cm and
// 1 deg), 40 % on walkers who moved 3-5 cm on top; a third of the room's landmarks with
// static evidence. RANSAC over two sampling pools, each sample scored against every
// weighted match, then GMC under each distinct hypothesis.
void BM_BackgroundSelect(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(40, 600), v(40, 440), z(1.0, 4.0), noise(-0.004, 0.004);
  gmc::Isometry motion = gmc::Isometry::Identity();
  motion.linear() = Eigen::AngleAxisd(M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  motion.translation() = Eigen::Vector3d(0.02, 0, 0);
  std::vector<gmc::MotionMatch> matches(static_cast<size_t>(n));
  gmc::vo::MatchTrust trust;
  for (int i = 0; i < n; ++i) {
    auto& m = matches[static_cast<size_t>(i)];
    m.pixel = Eigen::Vector2f(static_cast<float>(u(rng)), static_cast<float>(v(rng)));
    const double depth = z(rng);
    m.point_cur = Eigen::Vector3d((m.pixel.x() - 320) / 525.0 * depth, (m.pixel.y() - 240) / 525.0 * depth, depth);
    const bool room = i % 5 < 3;
    const Eigen::Vector3d walked = room ? Eigen::Vector3d::Zero() : Eigen::Vector3d(0.03 + 0.02 * (i % 2), 0, 0);
    m.point_ref = motion * m.point_cur + walked + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    trust.weight.push_back(1.0);
    trust.established.push_back(room && i % 3 == 0 ? 1 : 0);
    trust.known_dynamic.push_back(0);
  }
  gmc::vo::BackgroundOptions options;
  if (state.range(1) > 0) options.ransac_iterations = static_cast<int>(state.range(1));
  gmc::vo::BackgroundSelector selector(options, gmc::GmcParams{});
  gmc::vo::SelectionContext context;
  gmc::vo::BackgroundChoice choice;
  for (auto _ : state) {
    selector.select(matches, trust, context, choice);
    benchmark::DoNotOptimize(choice.score);
  }
}
// Second argument: RANSAC samples per pool (0 = the default).
BENCHMARK(BM_BackgroundSelect)
    ->Args({300, 0})
    ->Args({600, 0})
    ->Args({1200, 0})
    ->Args({600, 1000})
    ->Unit(benchmark::kMillisecond);

}  // namespace
