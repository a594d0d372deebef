// Golden checksums of GmcClassifier's whole output (labels, cells, clusters, counters) on
// generated cases. The expected values were recorded with the 457-line classify() before
// it was split into named steps (commit "tests/gmc: golden checksums ..."), so any
// refactoring must reproduce the old outputs bit for bit. Set GMC_PRINT_GOLDEN=1 to
// print the current checksums in the table's format.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "synthetic_matches.h"

namespace {

using namespace gmc;
using gmc::synth::Mover;
using gmc::synth::Scenario;

/// FNV-1a over raw bytes: any change of a label, count or float bit changes the sum.
class Fnv {
 public:
  template <class T>
  void add(const T& v) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    for (unsigned char b : bytes) h_ = (h_ ^ b) * 1099511628211ull;
  }
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 1469598103934665603ull;
};

std::uint64_t checksum(const GmcResult& r) {
  Fnv f;
  f.add(r.labels.size());
  for (auto l : r.labels) f.add(static_cast<int>(l));
  f.add(r.cells.size());
  for (const auto& c : r.cells) {
    for (int v : {c.x0, c.y0, c.x1, c.y1, c.depth, c.num_points, c.pattern_x, c.pattern_y,
                  c.pattern_z, c.binning, c.winner_count, c.second_count, c.cluster})
      f.add(v);
    for (int k = 0; k < 3; ++k) f.add(c.motion[k]);
  }
  f.add(r.clusters.size());
  for (const auto& c : r.clusters) {
    f.add(c.support);
    for (int k = 0; k < 3; ++k) f.add(c.mean_residual[k]);
    for (int k = 0; k < 3; ++k) f.add(c.mean_motion[k]);
    f.add(c.is_static);
  }
  for (int v : {r.static_cluster, static_cast<int>(r.static_fallback), r.iterations, r.grid_cols,
                r.grid_rows, r.num_static, r.num_dynamic, r.num_undecided})
    f.add(v);
  return f.value();
}

Mover box(double u0, double v0, double w, double h, double depth, double vx, double vz) {
  return {u0, v0, u0 + w, v0 + h, depth, Eigen::Vector3d(vx, 0, vz)};
}

GmcParams halfIntervals() {
  GmcParams p;
  p.e_int_x = p.e_int_z = p.e_int_y = 0.5;
  return p;
}

struct GoldenCase {
  const char* name;
  Scenario scenario;
  GmcParams params;
  Isometry guess_error = Isometry::Identity();  ///< applied to the true motion as the guess
};

Scenario scenario(std::vector<Mover> movers, unsigned seed, int n = 1500, double gap = 1,
                  double noise = 0.5) {
  Scenario s;
  s.movers = std::move(movers);
  s.seed = seed;
  s.num_matches = n;
  s.frame_gap = gap;
  s.pixel_noise = noise;
  s.T_ref_cur = synth::cameraMotion(0.01 * gap, -0.003, 0.008 * gap, 0.3 * gap);
  return s;
}

GmcParams variant(void (*edit)(GmcParams&)) {
  GmcParams p;
  edit(p);
  return p;
}

std::vector<GoldenCase> cases() {
  const auto walkers = [] {
    return std::vector<Mover>{{100, 80, 228, 430, 1.8, Eigen::Vector3d(1.0, 0, 0.2)},
                              {380, 60, 520, 440, 2.6, Eigen::Vector3d(-0.8, 0, 0.5)}};
  };
  const auto three = [] {
    return std::vector<Mover>{box(40, 120, 96, 280, 1.5, 1.0, 0), box(300, 60, 128, 360, 2.5, -0.8, 0.5),
                              box(500, 200, 100, 200, 4.0, 0, -1.5)};
  };
  Scenario covering = scenario({box(0, 0, 420, 480, 1.2, 1.0, 0.3)}, 41);
  covering.T_ref_cur = synth::cameraMotion(0.01, 0, 0.01, 0.5);
  return {
      {"bench walkers 500", scenario(walkers(), 99, 500), {}},
      {"bench walkers 2000", scenario(walkers(), 99, 2000), {}},
      {"bench walkers 5000", scenario(walkers(), 99, 5000), {}},
      {"walker 3 cells half intervals", scenario({box(300, 100, 96, 300, 2.0, 1.0, 0)}, 11), halfIntervals()},
      {"three movers gap 3", scenario(three(), 17, 1500, 3), halfIntervals()},
      {"three movers 1 px default", scenario(three(), 113, 1500, 3, 1.0), {}},
      {"straddling mover", scenario({box(208, 80, 112, 304, 2.0, 1.2, 0)}, 21, 2500), halfIntervals()},
      {"walker covers 2/3", covering, halfIntervals()},
      {"static scene", scenario({}, 3), halfIntervals()},
      {"guess far off (fallback)", scenario(walkers(), 7, 2000), {}, synth::cameraMotion(0.05, 0.02, -0.04, 2.0)},
      {"sparse 120 matches", scenario(walkers(), 5, 120), {}},
      {"use_y", scenario(walkers(), 8, 2000), variant([](GmcParams& p) { p.use_y = true; })},
      {"z power 1.5, depth 3", scenario(walkers(), 9, 2000),
       variant([](GmcParams& p) { p.z_depth_power = 1.5; p.max_depth = 3; })},
      {"fixed grid, depth 0", scenario(three(), 10, 1500, 3),
       variant([](GmcParams& p) { p.min_matches_per_cell = 0; p.max_depth = 0; })},
      {"disabled", scenario(walkers(), 12, 800), variant([](GmcParams& p) { p.enabled = false; })},
  };
}

/// Some matches made invalid (zero / NaN depth, NaN or outside pixel), as in real frames.
void spoil(std::vector<MotionMatch>& matches) {
  for (size_t i = 0; i < matches.size(); i += 13) matches[i].point_cur.z() = 0;
  for (size_t i = 5; i < matches.size(); i += 29) matches[i].point_ref.x() = std::nan("");
  if (matches.size() > 3) matches[3].pixel = Eigen::Vector2f(700, 10);
}

TEST(GmcGolden, OutputsMatchTheRecordedChecksums) {
  const bool print = std::getenv("GMC_PRINT_GOLDEN") != nullptr;
  const std::vector<std::uint64_t> expected = {
      0xf6e85a5e304d6959ull,  // bench walkers 500
      0xb2a90733c3a71470ull,  // bench walkers 500, spoiled
      0x30b1e6792d8093dbull,  // bench walkers 2000
      0xd63c97d440581223ull,  // bench walkers 2000, spoiled
      0x30d8b79c38bcebbbull,  // bench walkers 5000
      0xed0559817e791377ull,  // bench walkers 5000, spoiled
      0xdb2e56a5e4bc38d6ull,  // walker 3 cells half intervals
      0x2ff91eb2baa9a7eaull,  // walker 3 cells half intervals, spoiled
      0xd9342b20803e012aull,  // three movers gap 3
      0xf3bc0a46e0474c96ull,  // three movers gap 3, spoiled
      0x530925e2968b2561ull,  // three movers 1 px default
      0xbe7d0950f91fbb34ull,  // three movers 1 px default, spoiled
      0x278975dd123b08d6ull,  // straddling mover
      0x4bef1241d2fcb7beull,  // straddling mover, spoiled
      0x5baa77891d61a4d2ull,  // walker covers 2/3
      0xdad91008d94b28f9ull,  // walker covers 2/3, spoiled
      0x00dd55fd4a998837ull,  // static scene
      0xa81e200e6cd141d5ull,  // static scene, spoiled
      0xa022ff69b6cd39a5ull,  // guess far off (fallback)
      0xa3abdbc12a554c8aull,  // guess far off (fallback), spoiled
      0x18ce80d13f009e42ull,  // sparse 120 matches
      0xd7aa0729d65ae392ull,  // sparse 120 matches, spoiled
      0xab3e93c3ee5ec463ull,  // use_y
      0xa1ea8bea5df8051eull,  // use_y, spoiled
      0xa8b7e02021ed0deaull,  // z power 1.5, depth 3
      0xc93744f13e9dcc60ull,  // z power 1.5, depth 3, spoiled
      0xbca18f847e8e9b2aull,  // fixed grid, depth 0
      0xc3f78cd0f5c8cd3eull,  // fixed grid, depth 0, spoiled
      0x64963556714a850full,  // disabled
      0x5fd9b9aefc142b6cull,  // disabled, spoiled
  };
  size_t k = 0;
  int fallbacks = 0;
  for (const auto& c : cases()) {
    // One classifier and one result per case, reused as the odometry does: the second
    // call must not depend on what the first left in the buffers.
    GmcClassifier gmc(c.params);
    GmcResult result;
    for (bool spoiled : {false, true}) {
      auto g = synth::generate(c.scenario);
      if (spoiled) spoil(g.matches);
      gmc.classify(g.matches, c.scenario.T_ref_cur * c.guess_error, 640, 480, result);
      const std::uint64_t sum = checksum(result);
      fallbacks += result.static_fallback;
      if (print) std::printf("      0x%016llxull,  // %s%s\n", static_cast<unsigned long long>(sum), c.name, spoiled ? ", spoiled" : "");
      if (k < expected.size()) {
        EXPECT_EQ(sum, expected[k]) << c.name << (spoiled ? ", spoiled" : "");
      }
      ++k;
    }
  }
  EXPECT_GT(fallbacks, 0) << "no case exercises the largest-cluster fallback";
  if (!print) {
    EXPECT_EQ(expected.size(), k) << "table and cases differ in length";
  }
}

// GMS keep-flags on generated cases, recorded before GmsRun::run was split into steps.
TEST(GmsGolden, KeepFlagsMatchTheRecordedChecksums) {
  const bool print = std::getenv("GMC_PRINT_GOLDEN") != nullptr;
  const std::vector<std::uint64_t> expected = {
      0xcede1203b903e9ebull,
      0xd9d50472734e2202ull,
      0x3fd06af7802265faull,
      0x5c9c3dcf8b2f43b5ull,
      0xac9f3556a3e5c06dull,
      0x0bc48d9192e90ef6ull,
      0xb2f0ae0147fee8bbull,
      0xa6742d29afcde00aull,
      0xfdcd3c59865fe479ull,
  };
  GmsParams rotation_scale;
  rotation_scale.with_rotation = rotation_scale.with_scale = true;
  GmsParams fixed_grid;
  fixed_grid.min_matches_per_cell = 0;
  size_t k = 0;
  for (const GmsParams& params : {GmsParams{}, rotation_scale, fixed_grid}) {
    for (int n : {300, 1000, 3000}) {
      const auto c = synth::makeGmsCase(n, 0.5, static_cast<unsigned>(n), 12, -7, n == 300 ? 150 : 0);
      Fnv f;
      for (auto keep : gmsFilter(c.kp1, 640, 480, c.kp2, 640, 480, c.matches, params)) f.add(keep);
      if (print) std::printf("      0x%016llxull,\n", static_cast<unsigned long long>(f.value()));
      if (k < expected.size()) {
        EXPECT_EQ(f.value(), expected[k]) << "case " << k;
      }
      ++k;
    }
  }
  if (!print) {
    EXPECT_EQ(expected.size(), k);
  }
}

}  // namespace
