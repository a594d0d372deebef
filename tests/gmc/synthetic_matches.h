#pragma once
// Synthetic correspondences for GMC/GMS tests and benchmarks: a static background seen
// by a moving Kinect-like camera, plus rigid movers (boxes facing the camera) that
// occlude it. Noise: keypoint position (px) and depth sigma(z) = 1.2 mm + 1.9 mm (z-0.4)^2.
#include <random>
#include <vector>

#include "gmc/gmc/gmc.h"
#include "gmc/gmc/gms.h"

namespace gmc::synth {

struct Mover {
  double u0, v0, u1, v1;            ///< pixel rectangle in the current image
  double depth;                     ///< m
  Eigen::Vector3d velocity;         ///< m/s in the current camera frame
};

struct Scenario {
  int num_matches = 1500;
  double frame_gap = 1.0;           ///< frames between reference and current (30 Hz)
  double pixel_noise = 0.5;         ///< px, sigma
  bool depth_noise = true;
  std::vector<Mover> movers;
  Isometry T_ref_cur = Isometry::Identity();
  unsigned seed = 1;
};

struct Generated {
  std::vector<MotionMatch> matches;
  std::vector<bool> dynamic;        ///< ground truth per match
};

inline double kinectSigma(double z) { return 0.0012 + 0.0019 * (z - 0.4) * (z - 0.4); }

/// Background depth: a smooth room-like surface between ~1.5 and ~5.5 m.
inline double backgroundDepth(double u, double v) {
  return 3.5 + 1.2 * std::sin(u / 160.0) + 0.8 * std::cos(v / 120.0);
}

inline Generated generate(const Scenario& s, const PinholeCamera& cam = {}) {
  std::mt19937 rng(s.seed);
  std::uniform_real_distribution<double> U(0, cam.width), V(0, cam.height);
  std::normal_distribution<double> N(0, 1);
  const double dt = s.frame_gap / 30.0;
  Generated g;
  g.matches.reserve(static_cast<size_t>(s.num_matches));
  auto noisy = [&](const Eigen::Vector3d& p) {  // observe a point with keypoint + depth noise
    const Eigen::Vector2d px = cam.project(p) + s.pixel_noise * Eigen::Vector2d(N(rng), N(rng));
    const double z = p.z() + (s.depth_noise ? kinectSigma(p.z()) * N(rng) : 0.0);
    return cam.unproject(px.x(), px.y(), z);
  };
  while (static_cast<int>(g.matches.size()) < s.num_matches) {
    const double u = U(rng), v = V(rng);
    const Mover* hit = nullptr;
    for (const auto& m : s.movers)
      if (u >= m.u0 && u < m.u1 && v >= m.v0 && v < m.v1 && (!hit || m.depth < hit->depth)) hit = &m;
    Eigen::Vector3d p_cur, p_ref;
    if (hit) {
      p_cur = cam.unproject(u, v, hit->depth);
      p_ref = s.T_ref_cur * (p_cur - hit->velocity * dt);
    } else {
      p_cur = cam.unproject(u, v, backgroundDepth(u, v));
      p_ref = s.T_ref_cur * p_cur;
    }
    if (p_ref.z() < 0.3) continue;
    MotionMatch m;
    m.pixel = cam.project(p_cur).cast<float>();
    m.point_cur = noisy(p_cur);
    m.point_ref = noisy(p_ref);
    g.matches.push_back(m);
    g.dynamic.push_back(hit != nullptr);
  }
  return g;
}

/// A typical hand-held inter-frame camera motion.
inline Isometry cameraMotion(double tx, double ty, double tz, double yaw_deg) {
  Isometry T = Isometry::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(tx, ty, tz);
  return T;
}

struct Score {
  int tp = 0, fp = 0, fn = 0, undecided = 0;
  double precision() const { return tp + fp ? static_cast<double>(tp) / (tp + fp) : 1.0; }
  double recall() const { return tp + fn ? static_cast<double>(tp) / (tp + fn) : 1.0; }
};

/// Dynamic-match precision/recall; Undecided counts as "not dynamic".
inline Score score(const GmcResult& r, const Generated& g) {
  Score s;
  for (size_t i = 0; i < g.dynamic.size(); ++i) {
    const bool pred = r.labels[i] == MotionLabel::Dynamic;
    s.undecided += r.labels[i] == MotionLabel::Undecided;
    if (pred && g.dynamic[i]) ++s.tp;
    if (pred && !g.dynamic[i]) ++s.fp;
    if (!pred && g.dynamic[i]) ++s.fn;
  }
  return s;
}

/// GMS input: keypoints in two images with true matches and random outliers.
struct GmsCase {
  std::vector<GmsKeypoint> kp1, kp2;
  std::vector<GmsMatch> matches;
  std::vector<bool> is_true;
};

/// Keypoints within `radius` px of the image centre (0 = whole image).
inline GmsCase makeGmsCase(int num_true, double outlier_ratio, unsigned seed, double shift_x = 12,
                           double shift_y = -7, double radius = 0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(0, 640), V(0, 480);
  std::normal_distribution<double> N(0, 1.0);
  GmsCase c;
  const int num_out = static_cast<int>(std::lround(num_true * outlier_ratio / (1 - outlier_ratio)));
  for (int i = 0; i < num_true + num_out; ++i) {
    float x = static_cast<float>(U(rng)), y = static_cast<float>(V(rng));
    while (radius > 0 && std::hypot(x - 320.0, y - 240.0) > radius) {
      x = static_cast<float>(U(rng));
      y = static_cast<float>(V(rng));
    }
    c.kp1.push_back({x, y, 31, 0});
    if (i < num_true) {
      // A smooth image motion: shift plus a mild zoom about the centre.
      const double zx = (x - 320) * 0.02, zy = (y - 240) * 0.02;
      c.kp2.push_back({static_cast<float>(x + shift_x + zx + N(rng)), static_cast<float>(y + shift_y + zy + N(rng)), 31, 0});
      c.is_true.push_back(true);
    } else {
      c.kp2.push_back({static_cast<float>(U(rng)), static_cast<float>(V(rng)), 31, 0});
      c.is_true.push_back(false);
    }
    c.matches.push_back({i, i});
  }
  return c;
}

}  // namespace gmc::synth
