#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "gmc/config/ini.h"
#include "gmc/sim/sim_config.h"
#include "gmc/sim/simulator.h"
#include "sim_test_helpers.h"

namespace {

using gmc::sim::SimOptions;
using gmc::sim::Simulator;


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

}  // namespace

/// Static pixels of frame i, back-projected with their depth and ground-truth pose and
/// projected into frame j, land where frame j sees the same surface (noise-free options).
void expectStaticPixelsReprojectExactly(const SimOptions& o, const std::string& name, int i, int j) {
  {
    const Simulator sim(o);
    const char* style = name.c_str();
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
    std::printf("  %-15s frames %d -> %d: %d static pixels checked: worst reprojection %.4f px, depth %.5f m\n", style,
                i, j, checked, worst_px, worst_depth);
    EXPECT_GT(checked, 300) << style;
    EXPECT_LT(worst_px, 0.5) << style;
    EXPECT_LT(worst_depth, 0.001) << style;
  }
}

namespace {

TEST(Simulator, StaticPixelsReprojectIntoOtherFramesExactly) {
  for (const char* style : {"xyz", "rpy", "halfsphere", "handheld", "follow", "walk"}) {
    SimOptions o = small(SimOptions::exact());
    o.trajectory.style = style;
    expectStaticPixelsReprojectExactly(o, style);
  }
}

TEST(Simulator, EveryRayHitsTheClosedRoom) {
  for (const char* style : {"static", "xyz", "rpy", "halfsphere", "handheld"}) {
    SimOptions o = SimOptions::exact();
    o.trajectory.style = style;
    const Simulator sim(o);
    for (int i : {0, 30, 95}) {
      const auto f = sim.renderFrame(i);
      cv::Mat missing = f.true_depth <= 0;
      std::vector<cv::Point> where;
      cv::findNonZero(missing, where);
      EXPECT_TRUE(where.empty()) << style << " frame " << i << ": " << where.size() << " pixels without a surface, first at "
                                 << where.front();
    }
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

// Quantisation rounds 1/z to multiples of disparity_step: depth comes in steps of
// z^2 * step (Bonn's Xtion: 0.003, 12 mm at 2 m, measured on its depth PNGs).
TEST(Simulator, DepthComesInStepsOfTheDisparityStep) {
  for (double step : {0.0015, 0.003}) {
    SimOptions o = small(SimOptions::exact());
    o.sensor.quantize = true;
    o.sensor.disparity_step = step;
    const auto f = Simulator(o).renderFrame(5);
    std::set<int> levels;  // raw depth values beyond 2 m (millimetre rounding stays below 7 % of a step)
    for (int v = 0; v < f.frame.depth.rows; ++v)
      for (int u = 0; u < f.frame.depth.cols; ++u) {
        const int raw = f.frame.depth.at<std::uint16_t>(v, u);
        if (raw >= 10000) levels.insert(raw);
      }
    ASSERT_GE(levels.size(), 3u) << "step " << step;
    std::vector<double> gaps;
    for (auto it = std::next(levels.begin()); it != levels.end(); ++it) {
      const double z = *it / 5000.0;
      gaps.push_back((*it - *std::prev(it)) / 5000.0 / (z * z));
    }
    const double smallest = *std::min_element(gaps.begin(), gaps.end());
    std::printf("  disparity step %.4f: %zu depth levels beyond 2 m, smallest gap / z^2 %.4f\n", step,
                levels.size(), smallest);
    EXPECT_NEAR(smallest, step, 0.15 * step);
  }
}

// A radial depth bias reads depth as z (1 + k r^2): the exact frame's depth is the true
// depth times that factor at every pixel (Bonn's Xtion: k = -0.14, corners 7.5 % short).
TEST(Simulator, RadialDepthBiasScalesDepthWithTheImageRadius) {
  SimOptions o = small(SimOptions::exact());
  o.sensor.depth_radial_bias = -0.14;
  const auto f = Simulator(o).renderFrame(5);
  const auto& c = f.frame.camera;
  int checked = 0, off = 0;
  for (int v = 0; v < f.frame.depth.rows; ++v)
    for (int u = 0; u < f.frame.depth.cols; ++u) {
      const double z = f.true_depth.at<double>(v, u);
      const int raw = f.frame.depth.at<std::uint16_t>(v, u);
      if (z <= 0 || raw == 0) continue;
      const double x = (u - c.cx) / c.fx, y = (v - c.cy) / c.fy;
      off += std::abs(raw / 5000.0 - z * (1 - 0.14 * (x * x + y * y))) > 1.01e-4;
      ++checked;
    }
  EXPECT_GT(checked, 1000);
  EXPECT_EQ(off, 0);
}

// A structured-light sensor's depth distortion: a fixed, smooth offset in disparity over
// the image, so that one surface reads differently from each view.
TEST(Simulator, DisparityDistortionIsAFixedSmoothPatternOverTheImage) {
  SimOptions o = small(SimOptions::exact());
  o.sensor.disparity_distortion = 0.002;
  const Simulator sim(o);
  // The offset 1/measured - 1/true at every pixel with depth, and how finely the uint16
  // depth (0.2 mm steps) resolves it there: 1e-4 / z^2.
  auto offsets = [&](int index, cv::Mat& resolution) {
    const auto f = sim.renderFrame(index);
    cv::Mat out(f.frame.depth.size(), CV_64F, cv::Scalar(NAN));
    resolution = cv::Mat(f.frame.depth.size(), CV_64F, cv::Scalar(0));
    for (int v = 0; v < out.rows; ++v)
      for (int u = 0; u < out.cols; ++u) {
        const double z = f.true_depth.at<double>(v, u);
        const int raw = f.frame.depth.at<std::uint16_t>(v, u);
        if (z <= 0 || raw == 0) continue;
        out.at<double>(v, u) = 5000.0 / raw - 1.0 / z;
        resolution.at<double>(v, u) = 1e-4 / (z * z);
      }
    return out;
  };
  cv::Mat ra, rb;
  const cv::Mat a = offsets(2, ra), b = offsets(40, rb);
  int compared = 0, differing = 0, rough = 0;
  double lowest = 1, highest = -1;
  for (int v = 0; v < a.rows; ++v)
    for (int u = 0; u + 1 < a.cols; ++u) {
      const double x = a.at<double>(v, u), tolerance = ra.at<double>(v, u);
      if (std::isnan(x)) continue;
      lowest = std::min(lowest, x + tolerance), highest = std::max(highest, x - tolerance);
      if (!std::isnan(b.at<double>(v, u))) {
        ++compared;
        differing += std::abs(x - b.at<double>(v, u)) > tolerance + rb.at<double>(v, u);
      }
      const double right = a.at<double>(v, u + 1);
      if (!std::isnan(right)) rough += std::abs(right - x) > 1e-4 + tolerance + ra.at<double>(v, u + 1);
    }
  EXPECT_GT(compared, 1000);
  EXPECT_EQ(differing, 0);  // the same at a pixel in every frame
  EXPECT_EQ(rough, 0);      // smooth
  EXPECT_LE(highest, 0.002);
  EXPECT_GE(lowest, -0.002);
  EXPECT_GT(highest - lowest, 0.001);  // a pattern, not an offset
}

/// Static surface samples on a 3 cm voxel hash, for nearest-sample queries.
class SampleIndex {
 public:
  explicit SampleIndex(const std::vector<Eigen::Vector3d>& points) : points_(points) {
    for (size_t k = 0; k < points.size(); ++k) cells_[key(points[k])].push_back(k);
  }
  double nearest(const Eigen::Vector3d& x) const {
    double best = std::numeric_limits<double>::infinity();
    const auto [i, j, k] = key(x);
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj)
        for (int dk = -1; dk <= 1; ++dk) {
          const auto it = cells_.find({i + di, j + dj, k + dk});
          if (it == cells_.end()) continue;
          for (size_t idx : it->second) best = std::min(best, (points_[idx] - x).norm());
        }
    return best;
  }

 private:
  using Key = std::tuple<int, int, int>;
  static Key key(const Eigen::Vector3d& x) {
    auto c = [](double v) { return static_cast<int>(std::floor(v / 0.03)); };
    return {c(x.x()), c(x.y()), c(x.z())};
  }
  std::vector<Eigen::Vector3d> points_;
  std::map<Key, std::vector<size_t>> cells_;
};

TEST(Simulator, StaticSurfaceSamplesMatchTheRenderedScene) {
  SimOptions o = small(SimOptions::exact());
  o.people.walkers = 0;
  o.people.sitting = true;  // its chair is static scene too
  o.trajectory.style = "halfsphere";
  const Simulator sim(o);
  const double spacing = 0.02;
  const auto samples = sim.staticSurfaceSamples(spacing);
  const SampleIndex index(samples);
  for (int frame : {0, 60}) {
    const auto f = sim.renderFrame(frame);
    const auto& cam = f.frame.camera;
    // Every static pixel lies on a sampled surface: within half a grid diagonal of a sample.
    double worst_gap = 0;
    int pixels = 0;
    for (int v = 0; v < cam.height; v += 2)
      for (int u = 0; u < cam.width; u += 2) {
        const double z = f.true_depth.at<double>(v, u);
        if (z <= 0 || f.mask.at<std::uint8_t>(v, u)) continue;
        const Eigen::Vector3d x = f.T_world_camera * cam.unproject(u, v, z);
        worst_gap = std::max(worst_gap, index.nearest(x));
        ++pixels;
      }
    // Every sample in view is on the surface the camera sees there, or hidden behind it.
    const gmc::Isometry T_c_w = f.T_world_camera.inverse();
    int visible = 0, floating = 0;
    for (const auto& p : samples) {
      const Eigen::Vector3d xc = T_c_w * p;
      if (xc.z() < 0.1) continue;
      const Eigen::Vector2d uv = cam.project(xc);
      bool smooth = false;
      const double z = interpolateDepth(f.true_depth, uv.x(), uv.y(), smooth);
      if (!smooth) continue;
      if (std::abs(z - xc.z()) < 1e-6) ++visible;
      else if (z > xc.z()) ++floating;
    }
    std::printf("  frame %d: %d static pixels, farthest from a sample %.4f m; %d samples visible, %d in "
                "front of the rendered surface\n", frame, pixels, worst_gap, visible, floating);
    EXPECT_GT(pixels, 3000);
    EXPECT_LE(worst_gap, spacing * std::sqrt(0.5) + 1e-9);
    EXPECT_GT(visible, 10000);
    EXPECT_EQ(floating, 0);
  }
}

TEST(Simulator, TexturesGiveCornersInEveryPartOfTheImage) {
  for (const char* style : {"static", "halfsphere"}) {
    SimOptions o = SimOptions::exact();
    o.people.walkers = 0;
    o.trajectory.style = style;
    const auto f = Simulator(o).renderFrame(30);
    cv::Mat gray;
    cv::cvtColor(f.frame.rgb, gray, cv::COLOR_BGR2GRAY);
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(gray, corners, 3000, 0.01, 5);
    // 8 x 6 cells of 80 x 80 px: a detector must find something to match in each.
    std::vector<int> counts(48, 0);
    for (const auto& c : corners) ++counts[static_cast<size_t>(static_cast<int>(c.y) / 80 * 8 + static_cast<int>(c.x) / 80)];
    const int fewest = *std::min_element(counts.begin(), counts.end());
    std::printf("  %-10s %zu GFTT corners, fewest in an 80x80 cell: %d\n", style, corners.size(), fewest);
    EXPECT_GE(fewest, 10) << style;
  }
}

TEST(Simulator, CameraTrajectoriesFollowTheirStyle) {
  SimOptions o = SimOptions::exact();
  auto poses = [&](const char* style) {
    o.trajectory.style = style;
    const Simulator sim(o);
    std::vector<gmc::Isometry> out;
    for (int i = 0; i < 300; i += 5) out.push_back(sim.cameraPose(i));
    return out;
  };
  auto spread = [](const std::vector<gmc::Isometry>& ps, auto value) {
    double worst = 0;
    for (const auto& p : ps) worst = std::max(worst, (value(p) - value(ps.front())).norm());
    return worst;
  };
  auto position = [](const gmc::Isometry& p) -> Eigen::Vector3d { return p.translation(); };
  auto rotation = [](const gmc::Isometry& p) -> Eigen::Matrix3d { return p.linear(); };
  auto lookAt = [&](const gmc::Isometry& p) -> Eigen::Vector3d {
    return p.translation() + o.trajectory.radius * p.linear().col(2);
  };

  const auto fixed = poses("static");
  EXPECT_EQ(spread(fixed, position), 0.0);
  EXPECT_EQ(spread(fixed, rotation), 0.0);
  // Level camera at the configured height, looking horizontally: optical y is world -z.
  EXPECT_NEAR(fixed[0].translation().z(), o.trajectory.height, 1e-12);
  EXPECT_NEAR(fixed[0].linear().col(1).z(), -1.0, 1e-12);

  const auto xyz = poses("xyz");
  EXPECT_EQ(spread(xyz, rotation), 0.0);
  EXPECT_GT(spread(xyz, position), o.trajectory.amplitude);
  EXPECT_LT(spread(xyz, position), 2 * o.trajectory.amplitude * std::sqrt(3.0));

  const auto rpy = poses("rpy");
  EXPECT_EQ(spread(rpy, position), 0.0);
  double widest = 0;
  for (const auto& p : rpy) widest = std::max(widest, Eigen::AngleAxisd(p.linear() * rpy[0].linear().transpose()).angle());
  EXPECT_GT(widest * 180 / M_PI, o.trajectory.rotation);

  const auto half = poses("halfsphere");  // on a sphere, always looking at its centre
  EXPECT_GT(spread(half, position), 1.0);
  EXPECT_LT(spread(half, lookAt), 1e-9);

  const auto hand = poses("handheld");
  EXPECT_GT(spread(hand, position), 0.05);
  EXPECT_GT(spread(hand, rotation), 0.05);
  for (const auto& set : {fixed, xyz, rpy, half, hand})
    for (const auto& p : set) EXPECT_LT((p.linear() * p.linear().transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(Simulator, AWalkerEntersAndLeavesTheView) {
  SimOptions o = small(SimOptions::exact());
  o.people.walkers = 1;
  o.trajectory.style = "static";
  const Simulator sim(o);
  int with = 0, without = 0;
  for (int i = 0; i < 600; i += 10) (cv::countNonZero(sim.renderFrame(i).mask) > 0 ? with : without)++;
  EXPECT_GT(with, 0);
  EXPECT_GT(without, 0);
}
/// Visitor that lists the keys of an options struct.
struct KeyLister {
  std::vector<std::string> keys;
  template <class... Rest>
  void operator()(const char* key, Rest&&...) { keys.push_back(key); }
  void choice(const char* key, const std::string&, std::initializer_list<const char*>, const char*) {
    keys.push_back(key);
  }
};

TEST(SimConfig, ShippedScenariosLoadAndTheReferenceListsEveryKey) {
  int scenarios = 0;
  for (const auto& e : std::filesystem::directory_iterator(GMC_SOURCE_DIR "/config/sim")) {
    if (e.path().extension() != ".ini") continue;
    const auto ini = gmc::cfg::loadIniFile(e.path().string());
    EXPECT_NO_THROW(gmc::sim::loadSimOptions(ini, e.path().string())) << e.path();
    ++scenarios;
  }
  EXPECT_GE(scenarios, 11);
  // walkers_xyz.ini documents every key: each section holds all of its struct's keys.
  const auto ini = gmc::cfg::loadIniFile(GMC_SOURCE_DIR "/config/sim/walkers_xyz.ini");
  SimOptions o;
  auto check = [&](const char* section, auto& options) {
    KeyLister lister;
    options.visit(lister);
    for (const auto& key : lister.keys)
      EXPECT_TRUE(ini.keyExists(section, key)) << "walkers_xyz.ini lacks [" << section << "] " << key;
  };
  check("Simulator", o.simulator);
  check("Camera", o.camera);
  check("Trajectory", o.trajectory);
  check("People", o.people);
  check("Sensor", o.sensor);
  check("Room", o.room);
}

}  // namespace
