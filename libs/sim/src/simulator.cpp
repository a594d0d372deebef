// Ray-cast renderer of a small analytic world (boxes, spheres, capsules). Every pixel's
// ray goes through the pixel's coordinates (u, v) exactly as PinholeCamera::project()
// maps points, so a static point projects back onto the pixel that saw it.
#include "gmc/sim/simulator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <thread>

#include <opencv2/imgproc.hpp>

#include "random.h"
#include "texture.h"

namespace gmc::sim {
namespace {

using detail::gaussian;
using detail::hash;
using detail::Material;
using detail::mix;
using detail::Pattern;
using detail::Rng;

constexpr double kInf = std::numeric_limits<double>::infinity();

enum class Shape : std::uint8_t { Box, Sphere, Capsule };

struct Primitive {
  Shape shape = Shape::Box;
  bool inside = false;       ///< the room: rays hit its far faces
  bool dynamic = false;      ///< part of a person
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();  ///< box min/max; sphere centre (a); capsule ends
  double radius = 0;
  Material material;         ///< boxes: reseeded per face; the room: per-face materials of the scene
};

/// Ray r(t) = o + t d (d need not be unit). Returns the nearest t > eps or +inf.
double intersect(const Primitive& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  constexpr double eps = 1e-6;
  switch (p.shape) {
    case Shape::Box: {
      double t0 = -kInf, t1 = kInf;
      for (int k = 0; k < 3; ++k) {
        const double inv = 1.0 / d[k];
        double ta = (p.a[k] - o[k]) * inv, tb = (p.b[k] - o[k]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (t0 > t1) return kInf;
      if (p.inside) return t1 > eps ? t1 : kInf;
      return t0 > eps ? t0 : kInf;
    }
    case Shape::Sphere: {
      const Eigen::Vector3d oc = o - p.a;
      const double A = d.squaredNorm(), B = oc.dot(d), C = oc.squaredNorm() - p.radius * p.radius;
      const double disc = B * B - A * C;
      if (disc < 0) return kInf;
      const double t = (-B - std::sqrt(disc)) / A;
      return t > eps ? t : kInf;
    }
    case Shape::Capsule: {
      const Eigen::Vector3d ba = p.b - p.a, oa = o - p.a;
      const double baba = ba.dot(ba), bard = ba.dot(d), baoa = ba.dot(oa), rdoa = d.dot(oa),
                   oaoa = oa.dot(oa), dd = d.dot(d);
      const double A = baba * dd - bard * bard;
      const double B = baba * rdoa - baoa * bard;
      const double C = baba * oaoa - baoa * baoa - p.radius * p.radius * baba;
      double h = B * B - A * C;
      if (h < 0) return kInf;
      double t = (-B - std::sqrt(h)) / A;
      const double y = baoa + t * bard;
      if (y > 0 && y < baba) return t > eps ? t : kInf;
      // Caps.
      const Eigen::Vector3d oc = y <= 0 ? oa : Eigen::Vector3d(o - p.b);
      const double Bc = d.dot(oc), Cc = oc.dot(oc) - p.radius * p.radius;
      h = Bc * Bc - dd * Cc;
      if (h < 0) return kInf;
      t = (-Bc - std::sqrt(h)) / dd;
      return t > eps ? t : kInf;
    }
  }
  return kInf;
}

/// Where a ray hit: normal, texture coordinates (m) local to the face, the face's extent.
struct SurfacePoint {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double s = 0, t = 0;          ///< t grows upwards on vertical faces
  double width = 0, height = 0; ///< extent of a box face along s and t
  int face = 0;                 ///< boxes: 2 * axis + (1 at the max side)
};

SurfacePoint surface(const Primitive& p, const Eigen::Vector3d& x) {
  SurfacePoint sp;
  switch (p.shape) {
    case Shape::Box: {
      int axis = 0;
      double best = kInf;
      bool at_max = false;
      for (int k = 0; k < 3; ++k) {
        const double dmin = std::abs(x[k] - p.a[k]), dmax = std::abs(x[k] - p.b[k]);
        if (dmin < best) best = dmin, axis = k, at_max = false;
        if (dmax < best) best = dmax, axis = k, at_max = true;
      }
      sp.normal = Eigen::Vector3d::Zero();
      sp.normal[axis] = (at_max ? 1 : -1) * (p.inside ? -1 : 1);
      sp.face = 2 * axis + (at_max ? 1 : 0);
      // Vertical faces: s runs horizontally, t up; horizontal faces: s = x, t = y.
      const int is = axis == 0 ? 1 : 0, it = axis == 2 ? 1 : 2;
      sp.s = x[is] - p.a[is], sp.t = x[it] - p.a[it];
      sp.width = p.b[is] - p.a[is], sp.height = p.b[it] - p.a[it];
      return sp;
    }
    case Shape::Sphere:
      sp.normal = (x - p.a).normalized();
      sp.s = std::atan2(sp.normal.y(), sp.normal.x()) * p.radius;
      sp.t = x.z() - p.a.z();
      return sp;
    case Shape::Capsule: {
      const Eigen::Vector3d axis = (p.b - p.a).normalized();
      const double along = (x - p.a).dot(axis);
      const Eigen::Vector3d radial = x - p.a - along * axis;
      sp.normal = radial.norm() > 1e-9 ? Eigen::Vector3d(radial.normalized()) : axis;
      const Eigen::Vector3d ref = std::abs(axis.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
      const Eigen::Vector3d e1 = axis.cross(ref).normalized(), e2 = axis.cross(e1);
      sp.s = std::atan2(radial.dot(e2), radial.dot(e1)) * p.radius;
      sp.t = along;
      return sp;
    }
  }
  return sp;
}

struct Person {
  // Walkers go back and forth between two ends of a path (z = 0).
  Eigen::Vector2d from = Eigen::Vector2d::Zero(), to = Eigen::Vector2d::Zero();
  double speed = 1, offset = 0, height = 1.75;
  Material top, bottom, skin;
  bool sitting = false;
  Eigen::Vector2d seat = Eigen::Vector2d::Zero();
};

void addCapsule(std::vector<Primitive>& out, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                double r, const Material& material) {
  Primitive p;
  p.shape = Shape::Capsule;
  p.a = a, p.b = b, p.radius = r, p.material = material, p.dynamic = true;
  out.push_back(p);
}

void addHead(std::vector<Primitive>& out, const Eigen::Vector3d& centre, const Material& skin) {
  Primitive head;
  head.shape = Shape::Sphere;
  head.a = centre, head.radius = 0.11, head.material = skin, head.dynamic = true;
  out.push_back(head);
}

/// Body parts of a person at time t (world frame, z up).
void posePerson(const Person& person, double time, std::vector<Primitive>& out) {
  const double k = person.height / 1.75;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  if (person.sitting) {
    const Eigen::Vector3d base(person.seat.x(), person.seat.y(), 0.45);
    const double wave = std::sin(2 * M_PI * time / 1.7), nod = 0.03 * std::sin(2 * M_PI * time / 2.3);
    addCapsule(out, base + 0.1 * up, base + Eigen::Vector3d(0, nod, 0.55 * k), 0.19, person.top);
    addHead(out, base + Eigen::Vector3d(0, nod * 1.5, 0.75 * k), person.skin);
    for (int side : {-1, 1}) {  // thighs forward (towards -y, the camera), shins down
      const Eigen::Vector3d hip = base + Eigen::Vector3d(0.1 * side, 0, 0.05);
      const Eigen::Vector3d knee = hip + Eigen::Vector3d(0, -0.42, 0);
      addCapsule(out, hip, knee, 0.08, person.bottom);
      addCapsule(out, knee, Eigen::Vector3d(knee.x(), knee.y(), 0.05), 0.07, person.bottom);
      const Eigen::Vector3d shoulder = base + Eigen::Vector3d(0.25 * side, 0, 0.5 * k);
      const double lift = side > 0 ? 0.6 + 0.5 * wave : 0.3 - 0.3 * wave;  // gesturing arms
      const Eigen::Vector3d hand = shoulder + 0.55 * Eigen::Vector3d(0.3 * side, -std::sin(lift), -std::cos(lift));
      addCapsule(out, shoulder, hand, 0.05, person.top);
    }
    return;
  }
  // Back and forth along the path, so walkers keep entering and leaving the view.
  const Eigen::Vector2d span = person.to - person.from;
  const double L = span.norm(), walked = person.offset + person.speed * time;
  const double d = std::fmod(walked, 2 * L);
  const bool outward = d < L;
  const Eigen::Vector2d at = person.from + span * ((outward ? d : 2 * L - d) / L);
  const Eigen::Vector2d heading = span.normalized() * (outward ? 1.0 : -1.0);
  const Eigen::Vector3d feet(at.x(), at.y(), 0), fwd(heading.x(), heading.y(), 0), side(-heading.y(), heading.x(), 0);
  const double swing = 0.45 * std::sin(2 * M_PI * walked / 1.4);  // 1.4 m stride
  addCapsule(out, feet + 1.0 * k * up, feet + 1.42 * k * up, 0.19, person.top);
  addHead(out, feet + 1.63 * k * up, person.skin);
  for (int s : {-1, 1}) {
    const double a = s * swing;
    const Eigen::Vector3d hip = feet + 0.92 * k * up + 0.1 * s * side;
    addCapsule(out, hip, hip + 0.85 * k * (std::sin(a) * fwd - std::cos(a) * up), 0.08, person.bottom);
    const Eigen::Vector3d shoulder = feet + 1.42 * k * up + 0.26 * s * side;
    addCapsule(out, shoulder, shoulder + 0.6 * k * (-std::sin(a) * fwd - std::cos(a) * up), 0.05, person.top);
  }
}

Eigen::Matrix3d rotX(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
Eigen::Matrix3d rotY(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix(); }
Eigen::Matrix3d rotZ(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

/// Optical-frame rotation looking along `forward` with world z up.
Eigen::Matrix3d lookRotation(const Eigen::Vector3d& forward) {
  const Eigen::Vector3d z = forward.normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();  // right
  const Eigen::Vector3d y = z.cross(x);                                        // down
  Eigen::Matrix3d R;
  R.col(0) = x, R.col(1) = y, R.col(2) = z;
  return R;
}

/// Runs fn(first, step) on `threads` threads: thread i takes rows i, i + threads, ...
/// Every pixel's result depends on the pixel only, so the output is the same for any count.
template <class Fn>
void forRowsInParallel(int threads, const Fn& fn) {
  std::vector<std::thread> pool;
  for (int i = 0; i < threads; ++i) pool.emplace_back(fn, i, threads);
  for (auto& th : pool) th.join();
}

}  // namespace

struct Simulator::Scene {
  std::vector<Primitive> statics;
  std::array<Material, 6> room_faces;  ///< the room box's faces: walls, floor (4), ceiling (5)
  std::vector<Person> people;
  Eigen::Vector3d camera_base;
  std::vector<double> handheld_phase;  // per axis and harmonic
};

SimOptions SimOptions::exact() {
  SimOptions o;
  o.sensor.depth_noise = false;
  o.sensor.quantize = false;
  o.sensor.edge_dropout = false;
  o.sensor.grazing_angle = 90;
  o.sensor.image_noise = 0;
  o.sensor.max_range = 100;
  return o;
}

Simulator::Simulator(const SimOptions& options) : options_(options), scene_(std::make_unique<Scene>()) {
  Rng rng{mix(static_cast<std::uint64_t>(options.simulator.seed) + 17)};
  auto box = [&](Eigen::Vector3d lo, Eigen::Vector3d hi, const Material& material) {
    Primitive p;
    p.a = lo, p.b = hi, p.material = material;
    scene_->statics.push_back(p);
  };
  auto furniture = [&](double scale) {
    return detail::randomMaterial(rng, Pattern::Tiles, scale, 0, 1, 0.5, 0.8, 0.15);
  };
  // Room 8 x 6 x 2.8 m, camera side at y = -3: tiled walls of one hue each, a parquet-like
  // floor, a pale ceiling. (Regular brick walls gave look-alike corners: worse odometry.)
  Primitive room;
  room.a = Eigen::Vector3d(-4, -3, 0), room.b = Eigen::Vector3d(4, 3, 2.8);
  room.inside = true;
  scene_->statics.push_back(room);
  for (int wall = 0; wall < 4; ++wall)
    scene_->room_faces[static_cast<size_t>(wall)] = detail::randomMaterial(rng, Pattern::Tiles, 0.25, 0, 1, 0.35, 0.8, 0.12);
  scene_->room_faces[4] = detail::randomMaterial(rng, Pattern::Tiles, 0.3, 0.05, 0.1, 0.55, 0.7, 0.06);
  scene_->room_faces[5] = detail::randomMaterial(rng, Pattern::Tiles, 0.4, 0, 1, 0.08, 0.8, 0.2);
  // Furniture along the back and side walls (out of the walking corridor).
  for (int i = 0; i < 4; ++i) {  // tables with legs
    const double x0 = -3.4 + 1.8 * i + rng.uniform(-0.2, 0.2), y0 = rng.uniform(1.9, 2.2);
    const double w = rng.uniform(0.9, 1.4), d = rng.uniform(0.6, 0.8), h = rng.uniform(0.7, 0.78);
    box({x0, y0, h - 0.04}, {x0 + w, y0 + d, h}, furniture(rng.uniform(0.08, 0.15)));
    const Material legs = furniture(0.1);
    for (double lx : {x0 + 0.03, x0 + w - 0.08})
      for (double ly : {y0 + 0.03, y0 + d - 0.08}) box({lx, ly, 0}, {lx + 0.05, ly + 0.05, h - 0.04}, legs);
    box({x0 + 0.2, y0 + 0.1, h}, {x0 + 0.2 + rng.uniform(0.2, 0.4), y0 + 0.4, h + rng.uniform(0.1, 0.35)},
        furniture(rng.uniform(0.04, 0.08)));  // something on the table
  }
  for (int side : {-1, 1}) {  // shelves and cabinets on the side walls
    box({side * 4.0 - (side > 0 ? 0.45 : -0.0), -1.5, 0}, {side * 4.0 + (side > 0 ? 0 : 0.45), -0.3, 2.0},
        furniture(rng.uniform(0.1, 0.18)));
    box({side * 4.0 - (side > 0 ? 0.5 : 0.0), 0.5, 0}, {side * 4.0 + (side > 0 ? 0 : 0.5), 1.6, 1.1},
        furniture(rng.uniform(0.1, 0.2)));
  }
  for (int i = 0; i < 5; ++i) {  // posters on the back wall
    const double x0 = -3.6 + 1.5 * i + rng.uniform(0, 0.4), z0 = rng.uniform(1.2, 1.6);
    box({x0, 2.97, z0}, {x0 + rng.uniform(0.5, 0.9), 3.0, z0 + rng.uniform(0.5, 0.9)},
        detail::randomMaterial(rng, Pattern::Poster, 0.1, 0, 1, 0.7, 0.9, 1.0));
  }
  box({2.6, -2.9, 0}, {3.4, -2.3, 0.9}, furniture(0.12));  // a box near the camera side
  const auto& po = options.people;
  scene_->camera_base = Eigen::Vector3d(0, -2.4, options.trajectory.height);
  auto dress = [&](Person& p) {
    p.top = detail::randomMaterial(rng, Pattern::Cloth, 0.07, 0, 1, 0.6, 0.85, 0.6);
    p.bottom = detail::randomMaterial(rng, Pattern::Cloth, 0.06, 0, 1, 0.5, 0.6, 0.3);
    p.skin = detail::randomMaterial(rng, Pattern::Skin, 0.05, 0.04, 0.09, rng.uniform(0.3, 0.6), rng.uniform(0.5, 0.9), 0);
  };
  // Walking paths cross the room from wall to wall at evenly spread distances; each end is
  // moved towards or away from the camera by up to path_slant / 2, never onto a neighbour's path.
  const double spacing = po.walkers > 1 ? (po.distance_max - po.distance_min) / (po.walkers - 1) : kInf;
  const double slant = std::min(0.5 * po.path_slant, 0.3 * spacing);
  const double corridor_near = scene_->camera_base.y() + 0.5, corridor_far = 1.5;
  for (int w = 0; w < po.walkers; ++w) {
    Person p;
    const double f = po.walkers > 1 ? static_cast<double>(w) / (po.walkers - 1) : 0.5;
    const double line_y = scene_->camera_base.y() + po.distance_min + f * (po.distance_max - po.distance_min);
    auto end_y = [&] { return std::clamp(line_y + rng.uniform(-slant, slant), corridor_near, corridor_far); };
    p.from = {-3.2, end_y()};
    p.to = {3.2, end_y()};
    p.speed = po.speed_min + (po.speed_max - po.speed_min) * rng.uniform(0, 1);
    p.offset = rng.uniform(0, 12.8);
    p.height = rng.uniform(1.6, 1.9);
    dress(p);
    scene_->people.push_back(p);
  }
  if (po.sitting) {
    Person p;
    p.sitting = true;
    p.seat = Eigen::Vector2d(0.9, scene_->camera_base.y() + 2.6);
    dress(p);
    scene_->people.push_back(p);
    box({0.65, p.seat.y() - 0.05, 0}, {1.15, p.seat.y() + 0.45, 0.43}, furniture(0.08));  // the chair
  }
  for (int k = 0; k < 18; ++k) scene_->handheld_phase.push_back(rng.uniform(0, 2 * M_PI));
}

Simulator::~Simulator() = default;

double Simulator::stamp(int index) const {
  return options_.simulator.start_stamp + index / options_.simulator.fps;
}

Isometry Simulator::cameraPose(int index) const {
  const auto& tr = options_.trajectory;
  const double t = index / options_.simulator.fps, T = tr.period, w = 2 * M_PI / T;
  const double rot = tr.rotation * M_PI / 180;
  Eigen::Matrix3d R = lookRotation(Eigen::Vector3d::UnitY());
  Eigen::Vector3d p = scene_->camera_base;
  if (tr.style == "xyz") {
    p += R * (tr.amplitude * Eigen::Vector3d(std::sin(w * t), 0.6 * std::sin(w * t / 0.7), 0.8 * std::sin(w * t / 1.3)));
  } else if (tr.style == "rpy") {
    R = R * rotY(rot * std::sin(w * t)) * rotX(0.8 * rot * std::sin(w * t / 0.8)) * rotZ(0.6 * rot * std::sin(w * t / 1.2));
  } else if (tr.style == "halfsphere") {
    const Eigen::Vector3d centre(0, scene_->camera_base.y() + tr.radius, 1.1);
    const double az = 0.5 * std::sin(w * t), el = 0.2 + 0.15 * std::sin(w * t / 0.6);
    p = centre + tr.radius * Eigen::Vector3d(std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el));
    R = lookRotation(centre - p);
  } else if (tr.style == "handheld") {
    Eigen::Vector3d dp, dr;
    for (int a = 0; a < 3; ++a) {
      double sp = 0, sr = 0;
      for (int h = 0; h < 3; ++h) {
        const double f = w * (1 + 0.7 * h + 0.13 * a);
        sp += std::sin(f * t + scene_->handheld_phase[static_cast<size_t>(a * 3 + h)]) / (h + 1);
        sr += std::sin(f * t * 1.3 + scene_->handheld_phase[static_cast<size_t>(9 + a * 3 + h)]) / (h + 1);
      }
      dp[a] = sp, dr[a] = sr;
    }
    p += R * (0.5 * tr.amplitude * dp);
    R = R * rotX(0.3 * rot * dr.x()) * rotY(0.3 * rot * dr.y()) * rotZ(0.15 * rot * dr.z());
  }
  Isometry T_wc = Isometry::Identity();
  T_wc.linear() = R;
  T_wc.translation() = p;
  return T_wc;
}

SimFrame Simulator::renderFrame(int index) const {
  const auto& co = options_.camera;
  const auto& so = options_.sensor;
  const int W = co.width, H = co.height;
  const double time = index / options_.simulator.fps;
  SimFrame out;
  out.T_world_camera = cameraPose(index);
  const Eigen::Matrix3d R = out.T_world_camera.linear();
  const Eigen::Vector3d o = out.T_world_camera.translation();

  std::vector<Primitive> prims = scene_->statics;
  const size_t num_static = prims.size();
  for (const auto& person : scene_->people) posePerson(person, time, prims);

  // Screen rectangle of every primitive (bounding sphere), so most pixels test few shapes.
  struct Rect { int u0, v0, u1, v1; };
  std::vector<Rect> rects(prims.size());
  for (size_t k = 0; k < prims.size(); ++k) {
    const Primitive& p = prims[k];
    Eigen::Vector3d centre;
    double radius;
    if (p.shape == Shape::Box) centre = 0.5 * (p.a + p.b), radius = 0.5 * (p.b - p.a).norm();
    else if (p.shape == Shape::Sphere) centre = p.a, radius = p.radius;
    else centre = 0.5 * (p.a + p.b), radius = 0.5 * (p.b - p.a).norm() + p.radius;
    const Eigen::Vector3d c = R.transpose() * (centre - o);
    if (p.inside || c.z() - radius < 0.05) {
      rects[k] = {0, 0, W, H};
      if (!p.inside && c.z() + radius < 0) rects[k] = {0, 0, 0, 0};
      continue;
    }
    const double zr = c.z() - radius;
    const double u = co.fx * c.x() / c.z() + co.cx, v = co.fy * c.y() / c.z() + co.cy;
    const double ru = co.fx * radius / zr + 2, rv = co.fy * radius / zr + 2;
    rects[k] = {std::max(0, static_cast<int>(u - ru)), std::max(0, static_cast<int>(v - rv)),
                std::min(W, static_cast<int>(u + ru) + 1), std::min(H, static_cast<int>(v + rv) + 1)};
  }

  cv::Mat zbuf(H, W, CV_64FC1, cv::Scalar(kInf));
  cv::Mat ids(H, W, CV_32SC1, cv::Scalar(-1));
  out.frame.rgb.create(H, W, CV_8UC3);
  out.mask = cv::Mat::zeros(H, W, CV_8UC1);
  out.true_depth = cv::Mat::zeros(H, W, CV_64FC1);
  cv::Mat cosines(H, W, CV_64FC1, cv::Scalar(1.0));
  const Eigen::Vector3d light = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  const std::uint64_t seed = static_cast<std::uint64_t>(options_.simulator.seed);

  std::vector<Eigen::Vector3d> rays(static_cast<size_t>(W) * static_cast<size_t>(H));
  // Thread `first` renders rows first, first + step, ...: interleaved rows share the work
  // evenly (people and near furniture crowd the lower half of the image).
  auto renderRows = [&](int first, int step) {
    for (int v = first; v < H; v += step)
      for (int u = 0; u < W; ++u)
        rays[static_cast<size_t>(v * W + u)] = R * Eigen::Vector3d((u - co.cx) / co.fx, (v - co.cy) / co.fy, 1.0);
    for (size_t k = 0; k < prims.size(); ++k) {
      const Rect& rc = rects[k];
      const int v_start = rc.v0 + ((first - rc.v0) % step + step) % step;  // first own row >= v0
      for (int v = v_start; v < rc.v1; v += step) {
        double* z = zbuf.ptr<double>(v);
        int* id = ids.ptr<int>(v);
        for (int u = rc.u0; u < rc.u1; ++u) {
          const double t = intersect(prims[k], o, rays[static_cast<size_t>(v * W + u)]);
          if (t < z[u]) z[u] = t, id[u] = static_cast<int>(k);
        }
      }
    }
    // Shade each pixel once, from its nearest surface.
    for (int v = first; v < H; v += step) {
      for (int u = 0; u < W; ++u) {
        const int k = ids.at<int>(v, u);
        auto& px = out.frame.rgb.at<cv::Vec3b>(v, u);
        if (k < 0) {
          px = cv::Vec3b(0, 0, 0);
          continue;
        }
        const double t = zbuf.at<double>(v, u);
        const Eigen::Vector3d& d = rays[static_cast<size_t>(v * W + u)];
        const Eigen::Vector3d x = o + t * d;
        const Primitive& prim = prims[static_cast<size_t>(k)];
        const SurfacePoint sp = surface(prim, x);
        const Material& material = prim.inside ? scene_->room_faces[static_cast<size_t>(sp.face)] : prim.material;
        const Eigen::Vector3d c = detail::textureColour(prim.shape == Shape::Box && !prim.inside
                                                            ? material.reseeded(static_cast<std::uint64_t>(sp.face))
                                                            : material,
                                                        sp.s, sp.t, sp.width, sp.height) *
                                  (0.6 + 0.4 * std::abs(sp.normal.dot(light)));
        const std::uint64_t h = hash(seed, static_cast<std::uint64_t>(index), static_cast<std::uint64_t>(v * W + u), 1);
        for (int ch = 0; ch < 3; ++ch) {
          const double noisy = c[2 - ch] + (so.image_noise > 0 ? so.image_noise * gaussian(mix(h + ch)) : 0.0);
          px[ch] = cv::saturate_cast<std::uint8_t>(noisy);
        }
        out.true_depth.at<double>(v, u) = t;  // d has unit z: t is the depth
        cosines.at<double>(v, u) = std::abs(sp.normal.dot(d.normalized()));
        if (static_cast<size_t>(k) >= num_static) out.mask.at<std::uint8_t>(v, u) = 255;
      }
    }
  };
  const int threads = std::max(1, std::min(options_.simulator.threads, H));
  forRowsInParallel(threads, renderRows);

  // Sensor model on the depth image (needs the neighbouring rows: after all are rendered).
  out.frame.depth = cv::Mat::zeros(H, W, CV_16UC1);
  const double cos_limit = std::cos(so.grazing_angle * M_PI / 180);
  const double disparity_step = 0.0015;  // 1/m: ~6 mm steps at 2 m, like a Kinect's 1/8 px
  forRowsInParallel(threads, [&](int first, int step) {
  for (int v = first; v < H; v += step)
    for (int u = 0; u < W; ++u) {
      double z = out.true_depth.at<double>(v, u);
      if (z <= 0 || z > so.max_range) continue;
      if (cosines.at<double>(v, u) < cos_limit) continue;
      if (so.edge_dropout) {
        bool edge = false;
        for (auto [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const int uu = u + du, vv = v + dv;
          if (uu < 0 || vv < 0 || uu >= W || vv >= H) continue;
          const double zn = out.true_depth.at<double>(vv, uu);
          if (zn <= 0 || std::abs(zn - z) > 0.05 * z) edge = true;
        }
        if (edge) continue;
      }
      if (so.depth_noise) {
        const std::uint64_t h = hash(seed, static_cast<std::uint64_t>(index), static_cast<std::uint64_t>(v * W + u), 2);
        z += (0.0012 + 0.0019 * (z - 0.4) * (z - 0.4)) * gaussian(h);
      }
      if (so.quantize) z = 1.0 / (std::round((1.0 / z) / disparity_step) * disparity_step);
      out.frame.depth.at<std::uint16_t>(v, u) =
          static_cast<std::uint16_t>(std::clamp(std::lround(z * 5000.0), 0L, 65535L));
    }
  });
  out.frame.stamp = stamp(index);
  out.frame.depth_units = 1.0 / 5000.0;
  out.frame.camera.fx = co.fx, out.frame.camera.fy = co.fy, out.frame.camera.cx = co.cx, out.frame.camera.cy = co.cy;
  out.frame.camera.width = W, out.frame.camera.height = H;
  char name[64];
  std::snprintf(name, sizeof name, "frame %d", index);
  out.frame.name = name;
  return out;
}

cv::Mat sideBySide(const SimFrame& frame, double max_depth) {
  cv::Mat depth8, depth_colour, mask_colour, out;
  frame.frame.depth.convertTo(depth8, CV_8U, 255.0 / (max_depth / frame.frame.depth_units));
  cv::applyColorMap(depth8, depth_colour, cv::COLORMAP_TURBO);
  depth_colour.setTo(cv::Scalar::all(0), frame.frame.depth == 0);
  cv::cvtColor(frame.mask, mask_colour, cv::COLOR_GRAY2BGR);
  cv::hconcat(std::vector<cv::Mat>{frame.frame.rgb, depth_colour, mask_colour}, out);
  return out;
}

std::vector<Eigen::Vector3d> Simulator::staticSurfaceSamples(double spacing) const {
  std::vector<Eigen::Vector3d> pts;
  for (const auto& p : scene_->statics) {
    if (p.shape != Shape::Box) continue;
    for (int axis = 0; axis < 3; ++axis)
      for (double face : {p.a[axis], p.b[axis]}) {
        const int i1 = (axis + 1) % 3, i2 = (axis + 2) % 3;
        for (double s = p.a[i1]; s <= p.b[i1] + 1e-9; s += spacing)
          for (double t = p.a[i2]; t <= p.b[i2] + 1e-9; t += spacing) {
            Eigen::Vector3d x;
            x[axis] = face, x[i1] = s, x[i2] = t;
            pts.push_back(x);
          }
      }
  }
  return pts;
}

}  // namespace gmc::sim
