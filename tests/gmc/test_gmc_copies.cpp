// Copies of a GmcClassifier are independent: each has its own buffers, so copies used
// from different threads give the results of independent instances (the header's "one
// per thread" contract). Before the fix, copies shared one workspace through a
// shared_ptr and raced.
#include <gtest/gtest.h>

#include <thread>

#include "synthetic_matches.h"

namespace {

using namespace gmc;

synth::Generated frame(unsigned seed, int n) {
  synth::Scenario s;
  s.movers = {{100, 80, 228, 430, 1.8, Eigen::Vector3d(1.0, 0, 0.2)},
              {380, 60, 520, 440, 2.6, Eigen::Vector3d(-0.8, 0, 0.5)}};
  s.num_matches = n;
  s.seed = seed;
  return synth::generate(s);
}

bool sameOutput(const GmcResult& a, const GmcResult& b) {
  if (a.labels != b.labels || a.cells.size() != b.cells.size() || a.clusters.size() != b.clusters.size())
    return false;
  for (size_t c = 0; c < a.clusters.size(); ++c)
    if (a.clusters[c].support != b.clusters[c].support || a.clusters[c].mean_motion != b.clusters[c].mean_motion)
      return false;
  for (size_t c = 0; c < a.cells.size(); ++c)
    if (a.cells[c].winner_count != b.cells[c].winner_count || a.cells[c].cluster != b.cells[c].cluster) return false;
  return a.static_cluster == b.static_cluster && a.iterations == b.iterations;
}

/// Classifies `g` `repeats` times with `gmc`; counts results that differ from `expected`.
int countWrong(GmcClassifier& gmc, const synth::Generated& g, const GmcResult& expected, int repeats) {
  int wrong = 0;
  GmcResult r;
  for (int k = 0; k < repeats; ++k) {
    gmc.classify(g.matches, Isometry::Identity(), 640, 480, r);
    wrong += !sameOutput(r, expected);
  }
  return wrong;
}

TEST(GmcCopies, CopiesUsedFromTwoThreadsGiveTheResultsOfIndependentInstances) {
  // Different sizes and scenes, so a shared buffer would be resized under the other thread.
  const auto a = frame(1, 3000), b = frame(2, 1200);
  const auto expected_a = GmcClassifier().classify(a.matches, Isometry::Identity(), 640, 480);
  const auto expected_b = GmcClassifier().classify(b.matches, Isometry::Identity(), 640, 480);
  GmcClassifier original;
  GmcClassifier copy_constructed(original);
  GmcClassifier copy_assigned;
  copy_assigned = original;
  int wrong_a = 0, wrong_b = 0, wrong_c = 0;
  std::thread ta([&] { wrong_a = countWrong(original, a, expected_a, 150); });
  std::thread tb([&] { wrong_b = countWrong(copy_constructed, b, expected_b, 150); });
  std::thread tc([&] { wrong_c = countWrong(copy_assigned, a, expected_a, 150); });
  ta.join();
  tb.join();
  tc.join();
  EXPECT_EQ(wrong_a, 0);
  EXPECT_EQ(wrong_b, 0);
  EXPECT_EQ(wrong_c, 0);
}

TEST(GmcCopies, CopyKeepsTheParameters) {
  GmcParams p;
  p.grid_cols = 12;
  p.p_min = 0.7;
  const GmcClassifier original(p);
  const GmcClassifier copy(original);
  EXPECT_EQ(copy.params().grid_cols, 12);
  EXPECT_EQ(copy.params().p_min, 0.7);
  GmcClassifier assigned;
  assigned = original;
  EXPECT_EQ(assigned.params().grid_cols, 12);
}

}  // namespace
