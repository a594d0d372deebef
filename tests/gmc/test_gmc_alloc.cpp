// classify() into a reused GmcResult allocates nothing once its buffers have grown.
// Counts global operator new calls (this file replaces it for the whole test binary).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "synthetic_matches.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

TEST(GmcAllocation, SteadyStateClassifyDoesNotAllocate) {
  gmc::synth::Scenario s;
  s.movers = {{100, 80, 228, 430, 1.8, Eigen::Vector3d(1.0, 0, 0.2)},
              {380, 60, 520, 440, 2.6, Eigen::Vector3d(-0.8, 0, 0.5)}};
  s.num_matches = 2000;
  const auto frame_a = gmc::synth::generate(s);
  s.seed = 2;
  s.num_matches = 1800;
  const auto frame_b = gmc::synth::generate(s);
  gmc::GmcClassifier gmc;
  gmc::GmcResult r;
  // Buffers grow to the larger of the two frames (cells, leaves, clusters differ).
  gmc.classify(frame_a.matches, s.T_ref_cur, 640, 480, r);
  gmc.classify(frame_b.matches, s.T_ref_cur, 640, 480, r);
  ASSERT_GT(r.num_dynamic, 0);
  const long before = g_allocations.load();
  gmc.classify(frame_b.matches, s.T_ref_cur, 640, 480, r);
  gmc.classify(frame_a.matches, s.T_ref_cur, 640, 480, r);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(r.num_dynamic, 0);
}

}  // namespace
