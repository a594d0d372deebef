#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "gmc/apps/sim_app.h"
#include "gmc/sim/simulator.h"
#include "run_app.h"
#include "test_data.h"

namespace {

using gmc::sim::SimOptions;
using gmc::sim::Simulator;
namespace fs = std::filesystem;

/// Quarter-resolution camera keeps the tests fast; geometry is the same.
SimOptions small(SimOptions o) {
  o.camera.width = 160, o.camera.height = 120;
  o.camera.fx /= 4, o.camera.fy /= 4, o.camera.cx = (o.camera.cx + 0.5) / 4 - 0.5, o.camera.cy = (o.camera.cy + 0.5) / 4 - 0.5;
  return o;
}

/// True when the 3 x 3 pixels around (x, y) lie on one plane: 1/z is affine there, so all
/// second differences vanish (a step between two parallel planes does not).
bool planar3x3(const cv::Mat& m, int x, int y) {
  if (x < 1 || y < 1 || x + 1 >= m.cols || y + 1 >= m.rows) return false;
  auto w = [&](int dx, int dy) {
    const double z = m.at<double>(y + dy, x + dx);
    return z > 0 ? 1.0 / z : std::numeric_limits<double>::quiet_NaN();
  };
  for (int k = -1; k <= 1; ++k) {
    const double du = w(-1, k) - 2 * w(0, k) + w(1, k), dv = w(k, -1) - 2 * w(k, 0) + w(k, 1);
    if (!(std::abs(du) < 1e-9 && std::abs(dv) < 1e-9)) return false;
  }
  return std::abs(w(-1, -1) - w(1, -1) - w(-1, 1) + w(1, 1)) < 1e-9;
}

/// Depth at a sub-pixel position. Inverse depth is affine in (u, v) on a plane, so it is
/// interpolated instead of depth; `smooth` is false across depth edges.
double interpolateDepth(const cv::Mat& m, double u, double v, bool& smooth) {
  const int x = static_cast<int>(std::floor(u)), y = static_cast<int>(std::floor(v));
  smooth = x >= 0 && y >= 0 && x + 1 < m.cols && y + 1 < m.rows;
  if (!smooth) return 0;
  const double a = m.at<double>(y, x), b = m.at<double>(y, x + 1), c = m.at<double>(y + 1, x), d = m.at<double>(y + 1, x + 1);
  smooth = planar3x3(m, x, y) && planar3x3(m, x + 1, y + 1);
  const double fx = u - x, fy = v - y;
  return 1.0 / ((1 / a * (1 - fx) + 1 / b * fx) * (1 - fy) + (1 / c * (1 - fx) + 1 / d * fx) * fy);
}

TEST(Simulator, StaticPixelsReprojectIntoOtherFramesExactly) {
  for (const char* style : {"xyz", "rpy", "halfsphere", "handheld"}) {
    SimOptions o = small(SimOptions::exact());
    o.trajectory.style = style;
    const Simulator sim(o);
    const int i = 3, j = 17;
    const auto fi = sim.renderFrame(i), fj = sim.renderFrame(j);
    const gmc::Isometry T_j_i = fj.T_world_camera.inverse() * fi.T_world_camera;
    const auto& cam = fi.frame.camera;
    int checked = 0;
    double worst_px = 0, worst_depth = 0;
    for (int v = 2; v < cam.height - 2; v += 3)
      for (int u = 2; u < cam.width - 2; u += 3) {
        const double zi = fi.true_depth.at<double>(v, u);
        if (zi <= 0 || fi.mask.at<std::uint8_t>(v, u)) continue;
        // Only pixels inside a surface in frame i too (not on a silhouette or thin part).
        if (!planar3x3(fi.true_depth, u, v)) continue;
        const Eigen::Vector3d Xj = T_j_i * cam.unproject(u, v, zi);
        if (Xj.z() <= 0.1) continue;
        const Eigen::Vector2d pj = cam.project(Xj);
        bool smooth = false;
        const double zj = interpolateDepth(fj.true_depth, pj.x(), pj.y(), smooth);
        // Something nearer in frame j hides the point: occluded. Farther would be an error.
        if (!smooth || zj < Xj.z() - 0.001) continue;
        const int a = static_cast<int>(std::lround(pj.x())), b = static_cast<int>(std::lround(pj.y()));
        if (fj.mask.at<std::uint8_t>(b, a)) continue;
        // Where frame j sees that surface: back-project p_j with frame j's depth, back into i.
        const Eigen::Vector3d back = T_j_i.inverse() * cam.unproject(pj.x(), pj.y(), zj);
        const Eigen::Vector2d pi = cam.project(back);
        worst_px = std::max(worst_px, (pi - Eigen::Vector2d(u, v)).norm());
        worst_depth = std::max(worst_depth, std::abs(zj - Xj.z()));
        ++checked;
      }
    std::printf("  %-10s %d static pixels checked: worst reprojection %.4f px, depth %.5f m\n", style,
                checked, worst_px, worst_depth);
    EXPECT_GT(checked, 300) << style;
    EXPECT_LT(worst_px, 0.5) << style;
    EXPECT_LT(worst_depth, 0.001) << style;
  }
}

TEST(Simulator, MaskIsExactlyWherePeopleAreNearest) {
  SimOptions with = small(SimOptions::exact());
  with.people.walkers = 3;
  with.people.sitting = true;
  SimOptions without = with;
  without.people.walkers = 0;
  without.people.sitting = false;
  const Simulator a(with), b(without);
  int people = 0;
  for (int f : {0, 40, 80}) {
    const auto fa = a.renderFrame(f), fb = b.renderFrame(f);
    for (int v = 0; v < fa.mask.rows; ++v)
      for (int u = 0; u < fa.mask.cols; ++u) {
        const double za = fa.true_depth.at<double>(v, u), zb = fb.true_depth.at<double>(v, u);
        if (fa.mask.at<std::uint8_t>(v, u) == 255) {
          ++people;
          ASSERT_LT(za, zb + 1e-9) << "a person pixel behind the static scene at " << u << "," << v;
        } else {
          // The chair of the seated person exists only in `with`; elsewhere depths agree.
          if (std::abs(za - zb) > 1e-9) {
            ASSERT_LT(za, zb) << u << "," << v;
          }
        }
        ASSERT_TRUE(fa.mask.at<std::uint8_t>(v, u) == 0 || fa.mask.at<std::uint8_t>(v, u) == 255);
      }
  }
  EXPECT_GT(people, 200);
}

TEST(Simulator, SensorEffectsCanBeSwitchedOff) {
  const Simulator exact(small(SimOptions::exact()));
  const auto f = exact.renderFrame(5);
  int mismatched = 0;
  for (int v = 0; v < f.mask.rows; ++v)
    for (int u = 0; u < f.mask.cols; ++u) {
      const double z = f.true_depth.at<double>(v, u);
      mismatched += std::abs(f.frame.depth.at<std::uint16_t>(v, u) / 5000.0 - z) > 1.01e-4;
    }
  EXPECT_EQ(mismatched, 0);
  SimOptions noisy = small(SimOptions{});
  const auto g = Simulator(noisy).renderFrame(5);
  EXPECT_GT(cv::norm(g.frame.rgb, f.frame.rgb, cv::NORM_L1), 0.0);
  int dropped = 0;
  for (int v = 0; v < g.mask.rows; ++v)
    for (int u = 0; u < g.mask.cols; ++u) dropped += g.frame.depth.at<std::uint16_t>(v, u) == 0;
  EXPECT_GT(dropped, 0);  // edges and grazing angles lose depth
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int runSim(std::vector<std::string> args) {
  return gmc::testdata::runApp<gmc::apps::SimApp>("gmc-sim", std::move(args));
}

TEST(SimApp, SameSeedGivesByteIdenticalOutput) {
  const auto root = gmc::testdata::scratchDir("sim_determinism");
  std::ofstream(root + "/s.ini") << "[Simulator]\nframes = 3\nthreads = 2\n[Camera]\nwidth = 160\nheight = 120\n"
                                    "fx = 133.85\nfy = 134.8\ncx = 79.9\ncy = 61.8\n";
  ASSERT_EQ(runSim({root + "/s.ini", "--out", root + "/a", "--seed", "7"}), 0);
  std::ofstream(root + "/t.ini") << "[Simulator]\nframes = 3\nthreads = 1\n[Camera]\nwidth = 160\nheight = 120\n"
                                    "fx = 133.85\nfy = 134.8\ncx = 79.9\ncy = 61.8\n";
  ASSERT_EQ(runSim({root + "/t.ini", "--out", root + "/b", "--seed", "7"}), 0);
  size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(root + "/a")) {
    if (!e.is_regular_file()) continue;
    const auto rel = fs::relative(e.path(), root + "/a");
    EXPECT_EQ(slurp(e.path()), slurp(fs::path(root + "/b") / rel)) << rel;
    ++files;
  }
  EXPECT_EQ(files, 3u * 3u + 5u);  // rgb, depth, masks per frame; lists, gt, rawlog, scene
  ASSERT_EQ(runSim({root + "/s.ini", "--out", root + "/c", "--seed", "8"}), 0);
  EXPECT_NE(slurp(root + "/a/rgb.txt"), "");
  EXPECT_NE(slurp(fs::path(root + "/a/rgb") / fs::directory_iterator(root + "/a/rgb")->path().filename()),
            slurp(fs::path(root + "/c/rgb") / fs::directory_iterator(root + "/c/rgb")->path().filename()));
}

TEST(SimApp, BadConfigurationIsNamed) {
  const auto root = gmc::testdata::scratchDir("sim_bad");
  std::ofstream(root + "/a.ini") << "[People]\nwalkerz = 2\n";
  EXPECT_EQ(runSim({root + "/a.ini", "--out", root + "/o"}), 1);
  std::ofstream(root + "/b.ini") << "[Trajectory]\nstyle = loop\n";
  EXPECT_EQ(runSim({root + "/b.ini", "--out", root + "/o"}), 1);
  EXPECT_EQ(runSim({root + "/a.ini"}), 2);
  EXPECT_EQ(runSim({root + "/a.ini", "--out", root + "/o", "--frames", "x"}), 2);
  EXPECT_FALSE(fs::exists(root + "/o"));
}

}  // namespace
