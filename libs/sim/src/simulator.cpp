// Ray-cast renderer of a small analytic world (boxes, spheres, capsules). Every pixel's
// ray goes through the pixel's coordinates (u, v) exactly as PinholeCamera::project()
// maps points, so a static point projects back onto the pixel that saw it.
#include "gmc/sim/simulator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>

#include <opencv2/imgproc.hpp>

#include "people.h"
#include "primitive.h"
#include "random.h"
#include "texture.h"

namespace gmc::sim {
namespace {

using detail::gaussian;
using detail::hash;
using detail::Material;
using detail::mix;
using detail::PathState;
using detail::Pattern;
using detail::Person;
using detail::Primitive;
using detail::Rng;
using detail::Shape;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kOfficeBack = 2.0;  ///< y of the office's back wall (the tiled room's is 3)

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
  Eigen::Vector2d walk_from = Eigen::Vector2d::Zero(), walk_to = Eigen::Vector2d::Zero();  ///< style walk
  double walk_far = 1.5;  ///< y of the farthest walking path (clear of the back furniture)
  cv::Mat disparity_offset;  ///< 1/m per pixel ([Sensor] disparity_distortion; empty when off)
};

namespace {

/// The sensor's fixed disparity offsets (1/m) over the image: a wave and a bowl, within
/// +-amplitude, computed once since they do not change from frame to frame.
cv::Mat disparityOffsets(const CameraOptions& co, double amplitude) {
  cv::Mat out(co.height, co.width, CV_64F);
  for (int v = 0; v < co.height; ++v)
    for (int u = 0; u < co.width; ++u) {
      const double x = static_cast<double>(u) / co.width - 0.5, y = static_cast<double>(v) / co.height - 0.5;
      out.at<double>(v, u) = amplitude * (0.6 * std::cos(2 * M_PI * 0.8 * x + 0.3) * std::cos(2 * M_PI * 0.6 * y + 1.1) +
                                          0.4 * (4 * (x * x + y * y) - 1));
    }
  return out;
}

}  // namespace

SimOptions SimOptions::exact() {
  SimOptions o;
  o.sensor.depth_noise = false;
  o.sensor.quantize = false;
  o.sensor.edge_dropout = false;
  o.sensor.grazing_angle = 90;
  o.sensor.image_noise = 0;
  o.sensor.max_range = 100;
  o.sensor.projector_baseline = 0;
  o.sensor.exposure = 0;
  return o;
}

namespace {

/// Builds the static scene; `rng` order is fixed, so a seed always gives the same room.
class RoomBuilder {
 public:
  RoomBuilder(std::vector<Primitive>& statics, Rng& rng) : statics_(statics), rng_(rng) {}

  void box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Material& material) {
    Primitive p;
    p.a = lo, p.b = hi, p.material = material;
    statics_.push_back(p);
  }
  Material furniture(double scale, double saturation = 0.5) {
    return detail::randomMaterial(rng_, Pattern::Tiles, scale, 0, 1, saturation, 0.8, 0.15);
  }

  /// Tiled walls of one hue each, a parquet-like floor, a pale ceiling, posters, shelves.
  /// (Regular brick walls gave look-alike corners: worse odometry.)
  void tiledRoom(std::array<Material, 6>& faces) {
    for (int wall = 0; wall < 4; ++wall)
      faces[static_cast<size_t>(wall)] = detail::randomMaterial(rng_, Pattern::Tiles, 0.25, 0, 1, 0.35, 0.8, 0.12);
    faces[4] = detail::randomMaterial(rng_, Pattern::Tiles, 0.3, 0.05, 0.1, 0.55, 0.7, 0.06);
    faces[5] = detail::randomMaterial(rng_, Pattern::Tiles, 0.4, 0, 1, 0.08, 0.8, 0.2);
    tables(0.5, 1.9, 2.2);
    for (int side : {-1, 1}) {  // shelves and cabinets on the side walls
      box({side * 4.0 - (side > 0 ? 0.45 : -0.0), -1.5, 0}, {side * 4.0 + (side > 0 ? 0 : 0.45), -0.3, 2.0},
          furniture(rng_.uniform(0.1, 0.18)));
      box({side * 4.0 - (side > 0 ? 0.5 : 0.0), 0.5, 0}, {side * 4.0 + (side > 0 ? 0 : 0.5), 1.6, 1.1},
          furniture(rng_.uniform(0.1, 0.2)));
    }
    for (int i = 0; i < 5; ++i) {  // posters on the back wall
      const double x0 = -3.6 + 1.5 * i + rng_.uniform(0, 0.4), z0 = rng_.uniform(1.2, 1.6);
      box({x0, 2.97, z0}, {x0 + rng_.uniform(0.5, 0.9), 3.0, z0 + rng_.uniform(0.5, 0.9)},
          detail::randomMaterial(rng_, Pattern::Poster, 0.1, 0, 1, 0.7, 0.9, 1.0));
    }
    box({2.6, -2.9, 0}, {3.4, -2.3, 0.9}, furniture(0.12));  // a box near the camera side
  }

  /// An office like the Bonn recordings': bare white walls and ceiling, a pale speckled (or plain)
  /// floor, a cable duct with sockets at 1 m, texture only on furniture below ~1.1 m
  /// (tables, chairs, cabinets, boxes) and on one small marker.
  void office(std::array<Material, 6>& faces, double back, bool plain_floor) {
    for (int f = 0; f < 6; ++f)
      faces[static_cast<size_t>(f)] = detail::randomMaterial(rng_, Pattern::Paint, 1.0, 0.1, 0.15, 0.05, 0.93, 0);
    // A speckled floor offers near, well-measured corners; the Bonn floor is plain and its
    // static texture is the furniture (doc/sim.md).
    faces[4] = detail::randomMaterial(rng_, plain_floor ? Pattern::Paint : Pattern::Speckle, plain_floor ? 1.0 : 0.012,
                                      0.55, 0.62, 0.12, 0.8, 0);
    tables(0.3, back - 0.95, back - 0.85);  // 3.5 m from the camera at rest
    const Material duct = detail::randomMaterial(rng_, Pattern::Paint, 1.0, 0.1, 0.15, 0.03, 0.88, 0);
    box({-3.97, back - 0.06, 0.95}, {3.97, back, 1.07}, duct);
    for (int side : {-1, 1}) {
      box({side > 0 ? 3.94 : -4.0, -2.9, 0.95}, {side > 0 ? 4.0 : -3.94, back - 0.1, 1.07}, duct);
      box({side * 4.0 - (side > 0 ? 0.5 : 0.0), back - 1.5, 0}, {side * 4.0 + (side > 0 ? 0 : 0.5), back - 0.4, 1.0},
          furniture(rng_.uniform(0.1, 0.2), 0.3));  // low cabinets
    }
    for (int i = 0; i < 8; ++i) {  // sockets along the duct
      const double x = -3.5 + i + rng_.uniform(0, 0.4);
      box({x, back - 0.08, 0.97}, {x + 0.16, back - 0.06, 1.05}, furniture(0.04, 0.1));
    }
    for (int i = 0; i < 4; ++i) {  // office chairs at the tables, boxes on the floor
      const double x = -3.0 + 1.8 * i + rng_.uniform(-0.3, 0.3), y = back - rng_.uniform(1.25, 1.1);
      const Material seat = furniture(0.05, 0.15);
      box({x, y, 0.42}, {x + 0.45, y + 0.45, 0.5}, seat);
      box({x, y + 0.4, 0.5}, {x + 0.45, y + 0.47, 1.0}, seat);
      box({x + 0.2, y + 0.2, 0}, {x + 0.25, y + 0.25, 0.42}, seat);
      box({x + 0.6, back - 0.5, 0}, {x + 0.6 + rng_.uniform(0.3, 0.5), back - 0.1, rng_.uniform(0.2, 0.4)},
          furniture(0.08));
    }
    const double mx = rng_.uniform(-1.5, 1.5);  // one small marker on the back wall
    box({mx, back - 0.03, 2.0}, {mx + 0.25, back, 2.25}, detail::randomMaterial(rng_, Pattern::Poster, 0.1, 0, 1, 0.1, 0.9, 0.2));
  }

 private:
  /// Tables with legs along the back wall, an object on each; front edges at y0 in [y_lo, y_hi].
  void tables(double saturation, double y_lo, double y_hi) {
    for (int i = 0; i < 4; ++i) {
      const double x0 = -3.4 + 1.8 * i + rng_.uniform(-0.2, 0.2), y0 = rng_.uniform(y_lo, y_hi);
      const double w = rng_.uniform(0.9, 1.4), d = rng_.uniform(0.6, 0.8), h = rng_.uniform(0.7, 0.78);
      box({x0, y0, h - 0.04}, {x0 + w, y0 + d, h}, furniture(rng_.uniform(0.08, 0.15), saturation));
      const Material legs = furniture(0.1, saturation);
      for (double lx : {x0 + 0.03, x0 + w - 0.08})
        for (double ly : {y0 + 0.03, y0 + d - 0.08}) box({lx, ly, 0}, {lx + 0.05, ly + 0.05, h - 0.04}, legs);
      box({x0 + 0.2, y0 + 0.1, h}, {x0 + 0.2 + rng_.uniform(0.2, 0.4), y0 + 0.4, h + rng_.uniform(0.1, 0.35)},
          furniture(rng_.uniform(0.04, 0.08), saturation));
    }
  }
  std::vector<Primitive>& statics_;
  Rng& rng_;
};

void dress(Person& p, Rng& rng, bool plain) {
  const Pattern cloth = plain ? Pattern::PlainCloth : Pattern::Cloth;
  p.top = detail::randomMaterial(rng, cloth, 0.07, 0, 1, 0.6, 0.85, 0.6);
  p.bottom = detail::randomMaterial(rng, cloth, 0.06, 0, 1, 0.5, 0.6, 0.3);
  p.skin = detail::randomMaterial(rng, Pattern::Skin, 0.05, 0.04, 0.09, rng.uniform(0.3, 0.6), rng.uniform(0.5, 0.9), 0);
}

}  // namespace

Simulator::Simulator(const SimOptions& options) : options_(options), scene_(std::make_unique<Scene>()) {
  Rng rng{mix(static_cast<std::uint64_t>(options.simulator.seed) + 17)};
  // Room 8 x 6 x 2.8 m, camera side at y = -3.
  Primitive room;
  // The office is shallower (back wall 4.4 m from the camera), as the Bonn office.
  const bool office = options.room.style == "office";
  room.a = Eigen::Vector3d(-4, -3, 0), room.b = Eigen::Vector3d(4, office ? kOfficeBack : 3.0, 2.8);
  room.inside = true;
  scene_->statics.push_back(room);
  scene_->walk_far = office ? kOfficeBack - 1.5 : 1.5;
  RoomBuilder builder(scene_->statics, rng);
  if (office) builder.office(scene_->room_faces, kOfficeBack, options.room.floor == "plain");
  else builder.tiledRoom(scene_->room_faces);
  scene_->camera_base = Eigen::Vector3d(0, -2.4, options.trajectory.height);
  addWalkers(rng);
  if (options.people.sitting) {
    Person p;
    p.sitting = true;
    p.seat = Eigen::Vector2d(0.9, scene_->camera_base.y() + 2.6);
    dress(p, rng, options.people.clothes == "plain");
    scene_->people.push_back(p);
    builder.box({0.65, p.seat.y() - 0.05, 0}, {1.15, p.seat.y() + 0.45, 0.43}, builder.furniture(0.08));  // the chair
  }
  for (int k = 0; k < 18; ++k) scene_->handheld_phase.push_back(rng.uniform(0, 2 * M_PI));
  if (options.sensor.disparity_distortion != 0)
    scene_->disparity_offset = disparityOffsets(options.camera, options.sensor.disparity_distortion);
}

void Simulator::addWalkers(Rng& rng) {
  const auto& po = options_.people;
  const bool plain = po.clothes == "plain";
  // Walking paths cross the room at evenly spread distances, centred in front of the
  // camera; each end is moved towards or away from the camera by up to path_slant / 2,
  // never onto a neighbour's path.
  const double spacing = po.walkers > 1 ? (po.distance_max - po.distance_min) / (po.walkers - 1) : kInf;
  const double slant = std::min(0.5 * po.path_slant, 0.3 * spacing);
  const double corridor_near = scene_->camera_base.y() + std::min(0.5, po.distance_min);
  const double corridor_far = scene_->walk_far;
  const bool follow = options_.trajectory.style == "follow";
  for (int w = 0; w < po.walkers; ++w) {
    Person p;
    const double f = po.walkers > 1 ? static_cast<double>(w) / (po.walkers - 1) : 0.5;
    const double line_y = scene_->camera_base.y() + po.distance_min + f * (po.distance_max - po.distance_min);
    auto end_y = [&] { return std::clamp(line_y + rng.uniform(-slant, slant), corridor_near, corridor_far); };
    p.from = {-0.5 * po.path_span, end_y()};
    p.to = {0.5 * po.path_span, end_y()};
    if (follow && w == 0) {  // the followed walker: a straight path in front of the camera
      const double y = scene_->camera_base.y() + options_.trajectory.follow_distance;
      p.from.y() = p.to.y() = y;
    }
    p.speed = po.speed_min + (po.speed_max - po.speed_min) * rng.uniform(0, 1);
    p.offset = rng.uniform(0, 12.8);
    p.height = rng.uniform(1.6, 1.9);
    dress(p, rng, plain);
    if (po.pause_max > 0) {  // drawn last: scenarios without stops keep their people
      p.pause = rng.uniform(po.pause_min, po.pause_max);
      p.stop = rng.uniform(0.3, 0.7);  // near the middle of the path: in view
    }
    scene_->people.push_back(p);
  }
  // The camera's walk (style walk) and the group in step with it: abreast or ahead of
  // the camera, 1.2-3 m in front, spread across the view.
  const auto& tr = options_.trajectory;
  scene_->walk_from = {-0.5 * tr.walk_span, scene_->camera_base.y()};
  scene_->walk_to = {0.5 * tr.walk_span, scene_->camera_base.y()};
  for (int g = 0; g < po.group; ++g) {
    Person p;
    p.with_camera = true;
    const double f = po.group > 1 ? static_cast<double>(g) / (po.group - 1) : 0.5;
    p.camera_offset = {(f - 0.5) * 1.2 + rng.uniform(-0.1, 0.1), 1.2 + 1.8 * f + rng.uniform(-0.2, 0.2)};
    p.speed = tr.walk_speed;
    p.offset = rng.uniform(0, 1.4);
    p.height = rng.uniform(1.6, 1.9);
    dress(p, rng, plain);
    scene_->people.push_back(p);
  }
}

Simulator::~Simulator() = default;

double Simulator::stamp(int index) const {
  return options_.simulator.start_stamp + index / options_.simulator.fps;
}

PathState Simulator::cameraWalk(double time) const {
  return detail::pathState(scene_->walk_from, scene_->walk_to, options_.trajectory.walk_speed, 0, time);
}

std::vector<Eigen::Vector3d> Simulator::peoplePositions(double time) const {
  std::vector<Eigen::Vector3d> out;
  const PathState walk = cameraWalk(time);
  for (const auto& person : scene_->people) {
    const Eigen::Vector2d at = person.sitting ? person.seat : detail::personState(person, walk, time).at;
    out.emplace_back(at.x(), at.y(), 0.0);
  }
  return out;
}

Eigen::Vector3d Simulator::handheldShake(double time, bool rotation) const {
  const double w = 2 * M_PI / options_.trajectory.period;
  Eigen::Vector3d out;
  for (int a = 0; a < 3; ++a) {
    double sum = 0;
    for (int h = 0; h < 3; ++h) {
      const double f = w * (1 + 0.7 * h + 0.13 * a) * (rotation ? 1.3 : 1.0);
      sum += std::sin(f * time + scene_->handheld_phase[static_cast<size_t>((rotation ? 9 : 0) + a * 3 + h)]) / (h + 1);
    }
    out[a] = sum;
  }
  return out;
}

Isometry Simulator::cameraPose(int index) const { return cameraPoseAt(index / options_.simulator.fps); }

Isometry Simulator::cameraPoseAt(double t) const {
  const auto& tr = options_.trajectory;
  const double T = tr.period, w = 2 * M_PI / T;
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
  } else if (tr.style == "handheld" || tr.style == "follow") {
    if (tr.style == "follow") {  // 3/4 of the walker's sideways motion, the rest by panning
      const Eigen::Vector2d at = detail::personState(scene_->people.front(), cameraWalk(t), t).at;
      p = Eigen::Vector3d(0.75 * at.x(), at.y() - tr.follow_distance, tr.height);
      R = lookRotation(Eigen::Vector3d(at.x(), at.y(), tr.height) - p);
    }
    const Eigen::Vector3d dp = handheldShake(t, false), dr = handheldShake(t, true);
    p += R * (0.5 * tr.amplitude * dp);
    R = R * rotX(0.3 * rot * dr.x()) * rotY(0.3 * rot * dr.y()) * rotZ(0.15 * rot * dr.z());
  } else if (tr.style == "walk") {
    const Eigen::Vector2d at = cameraWalk(t).at;
    p = Eigen::Vector3d(at.x(), at.y(), tr.height);
  }
  if (tr.style != "halfsphere") R = R * rotX(-tr.tilt * M_PI / 180);  // optical axis down
  Isometry T_wc = Isometry::Identity();
  T_wc.linear() = R;
  T_wc.translation() = p;
  return T_wc;
}

namespace {

/// Screen rectangle of a primitive (from its bounding sphere), so most pixels test few shapes.
struct Rect {
  int u0, v0, u1, v1;
};

/// Projected corners' bounding rectangle of a box entirely in front of the camera.
std::optional<Rect> boxRect(const Primitive& p, const Isometry& T_cw, const CameraOptions& co) {
  double u0 = kInf, v0 = kInf, u1 = -kInf, v1 = -kInf;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d x(corner & 1 ? p.b.x() : p.a.x(), corner & 2 ? p.b.y() : p.a.y(),
                            corner & 4 ? p.b.z() : p.a.z());
    const Eigen::Vector3d c = T_cw * x;
    if (c.z() < 0.05) return std::nullopt;
    const double u = co.fx * c.x() / c.z() + co.cx, v = co.fy * c.y() / c.z() + co.cy;
    u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  auto clampTo = [](double x, int hi) { return static_cast<int>(std::clamp(x, 0.0, static_cast<double>(hi))); };
  return Rect{clampTo(u0 - 2, co.width), clampTo(v0 - 2, co.height), clampTo(u1 + 3, co.width),
              clampTo(v1 + 3, co.height)};
}

Rect screenRect(const Primitive& p, const Isometry& T_wc, const CameraOptions& co) {
  if (p.shape == Shape::Box && !p.inside)
    if (const auto rect = boxRect(p, T_wc.inverse(), co)) return *rect;
  Eigen::Vector3d centre;
  double radius;
  if (p.shape == Shape::Box) centre = 0.5 * (p.a + p.b), radius = 0.5 * (p.b - p.a).norm();
  else if (p.shape == Shape::Sphere) centre = p.a, radius = p.radius;
  else centre = 0.5 * (p.a + p.b), radius = 0.5 * (p.b - p.a).norm() + p.radius;
  const Eigen::Vector3d c = T_wc.linear().transpose() * (centre - T_wc.translation());
  if (p.inside || c.z() - radius < 0.05) {
    if (!p.inside && c.z() + radius < 0) return {0, 0, 0, 0};
    return {0, 0, co.width, co.height};
  }
  const double zr = c.z() - radius;
  const double u = co.fx * c.x() / c.z() + co.cx, v = co.fy * c.y() / c.z() + co.cy;
  const double ru = co.fx * radius / zr + 2, rv = co.fy * radius / zr + 2;
  return {std::max(0, static_cast<int>(u - ru)), std::max(0, static_cast<int>(v - rv)),
          std::min(co.width, static_cast<int>(u + ru) + 1), std::min(co.height, static_cast<int>(v + rv) + 1)};
}

/// Nearest primitive along every ray of rows first, first + step, ... (each primitive
/// tested only inside its screen rectangle): depth into zbuf, primitive index into ids.
void castRays(const std::vector<Primitive>& prims, const std::vector<Rect>& rects, const Eigen::Vector3d& o,
              const std::vector<Eigen::Vector3d>& rays, int first, int step, cv::Mat& zbuf, cv::Mat& ids) {
  const int W = zbuf.cols;
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
}

}  // namespace

/// One noise-free view: colour (CV_64FC3, BGR 0-255), depth (CV_64F, m, 0 = nothing),
/// person mask, and |cos| of the incidence angle.
struct Simulator::View {
  cv::Mat colour, depth, mask, cosines;
};

Simulator::View Simulator::renderView(double time, const Isometry& T_wc) const {
  const auto& co = options_.camera;
  const int W = co.width, H = co.height;
  const Eigen::Matrix3d R = T_wc.linear();
  const Eigen::Vector3d o = T_wc.translation();
  std::vector<Primitive> prims = scene_->statics;
  const size_t num_static = prims.size();
  const PathState walk = cameraWalk(time);
  for (const auto& person : scene_->people)
    detail::posePerson(person, detail::personState(person, walk, time), time, options_.people.articulated, prims,
                       options_.people.fidget);
  std::vector<Rect> rects(prims.size());
  for (size_t k = 0; k < prims.size(); ++k) rects[k] = screenRect(prims[k], T_wc, co);

  cv::Mat zbuf(H, W, CV_64FC1, cv::Scalar(kInf));
  cv::Mat ids(H, W, CV_32SC1, cv::Scalar(-1));
  View view;
  view.colour = cv::Mat::zeros(H, W, CV_64FC3);
  view.mask = cv::Mat::zeros(H, W, CV_8UC1);
  view.depth = cv::Mat::zeros(H, W, CV_64FC1);
  view.cosines = cv::Mat(H, W, CV_64FC1, cv::Scalar(1.0));
  const Eigen::Vector3d light = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  std::vector<Eigen::Vector3d> rays(static_cast<size_t>(W) * static_cast<size_t>(H));
  // Thread `first` renders rows first, first + step, ...: interleaved rows share the work
  // evenly (people and near furniture crowd the lower half of the image).
  auto renderRows = [&](int first, int step) {
    for (int v = first; v < H; v += step)
      for (int u = 0; u < W; ++u)
        rays[static_cast<size_t>(v * W + u)] = R * Eigen::Vector3d((u - co.cx) / co.fx, (v - co.cy) / co.fy, 1.0);
    castRays(prims, rects, o, rays, first, step, zbuf, ids);
    // Shade each pixel once, from its nearest surface.
    for (int v = first; v < H; v += step) {
      for (int u = 0; u < W; ++u) {
        const int k = ids.at<int>(v, u);
        if (k < 0) continue;
        const double t = zbuf.at<double>(v, u);
        const Eigen::Vector3d& d = rays[static_cast<size_t>(v * W + u)];
        const Primitive& prim = prims[static_cast<size_t>(k)];
        const SurfacePoint sp = surface(prim, o + t * d);
        const Material& material = prim.inside ? scene_->room_faces[static_cast<size_t>(sp.face)] : prim.material;
        const Eigen::Vector3d c = detail::textureColour(prim.shape == Shape::Box && !prim.inside
                                                            ? material.reseeded(static_cast<std::uint64_t>(sp.face))
                                                            : material,
                                                        sp.s, sp.t, sp.width, sp.height) *
                                  (0.6 + 0.4 * std::abs(sp.normal.dot(light)));
        view.colour.at<cv::Vec3d>(v, u) = cv::Vec3d(c[2], c[1], c[0]);
        view.depth.at<double>(v, u) = t;  // d has unit z: t is the depth
        view.cosines.at<double>(v, u) = std::abs(sp.normal.dot(d.normalized()));
        if (static_cast<size_t>(k) >= num_static) view.mask.at<std::uint8_t>(v, u) = 255;
      }
    }
  };
  forRowsInParallel(renderThreads(), renderRows);
  return view;
}

int Simulator::renderThreads() const { return std::max(1, std::min(options_.simulator.threads, options_.camera.height)); }

SimFrame Simulator::renderFrame(int index) const {
  const auto& so = options_.sensor;
  const double time = index / options_.simulator.fps;
  SimFrame out;
  out.T_world_camera = cameraPose(index);
  View view = renderView(time, out.T_world_camera);
  // Motion blur: the colour integrated over the exposure (camera and people moving),
  // which ends at the frame's time; depth, mask and pose are those of that instant.
  if (so.exposure > 0) {
    cv::Mat sum = view.colour.clone();
    for (int k = 1; k < so.blur_samples; ++k) {
      const double tk = time - so.exposure * k / (so.blur_samples - 1);
      sum += renderView(tk, cameraPoseAt(tk)).colour;
    }
    view.colour = sum / so.blur_samples;
  }
  out.frame.rgb = addImageNoise(view.colour, index);
  out.mask = view.mask;
  out.true_depth = view.depth;
  out.frame.depth = sensorDepth(view, index);
  const auto& co = options_.camera;
  out.frame.stamp = stamp(index);
  out.frame.depth_units = 1.0 / 5000.0;
  out.frame.camera.fx = co.fx, out.frame.camera.fy = co.fy, out.frame.camera.cx = co.cx, out.frame.camera.cy = co.cy;
  out.frame.camera.width = co.width, out.frame.camera.height = co.height;
  char name[64];
  std::snprintf(name, sizeof name, "frame %d", index);
  out.frame.name = name;
  return out;
}

cv::Mat Simulator::addImageNoise(const cv::Mat& colour, int index) const {
  const double sigma = options_.sensor.image_noise;
  const std::uint64_t seed = static_cast<std::uint64_t>(options_.simulator.seed);
  cv::Mat rgb(colour.size(), CV_8UC3);
  const int W = colour.cols;
  forRowsInParallel(renderThreads(), [&](int first, int step) {
    for (int v = first; v < colour.rows; v += step)
      for (int u = 0; u < W; ++u) {
        const cv::Vec3d& c = colour.at<cv::Vec3d>(v, u);
        const std::uint64_t h = hash(seed, static_cast<std::uint64_t>(index), static_cast<std::uint64_t>(v * W + u), 1);
        auto& px = rgb.at<cv::Vec3b>(v, u);
        for (int ch = 0; ch < 3; ++ch)  
          px[ch] = cv::saturate_cast<std::uint8_t>(c[ch] + (sigma > 0 ? sigma * gaussian(mix(h + ch)) : 0.0));
      }
  });
  return rgb;
}

/// Pixels the projector cannot light (structured-light sensors): with the projector
/// `baseline` m right of the camera, a surface is shadowed where a nearer surface to its
/// right comes first along the projector's ray, i.e. where the projector column
/// u - f b / z is not increasing from right to left. Left of every person's silhouette
/// a band of f b (1/z_person - 1/z_wall) pixels loses depth, as on a Kinect.
cv::Mat Simulator::projectorShadows(const cv::Mat& depth) const {
  cv::Mat shadow = cv::Mat::zeros(depth.size(), CV_8UC1);
  const double fb = options_.camera.fx * options_.sensor.projector_baseline;
  if (fb <= 0) return shadow;
  for (int v = 0; v < depth.rows; ++v) {
    double nearest_column = kInf;  // smallest projector column among pixels to the right
    for (int u = depth.cols - 1; u >= 0; --u) {
      const double z = depth.at<double>(v, u);
      if (z <= 0) continue;
      const double column = u - fb / z;
      if (column > nearest_column + 1e-6) shadow.at<std::uint8_t>(v, u) = 255;
      nearest_column = std::min(nearest_column, column);
    }
  }
  return shadow;
}

/// The Kinect-like sensor model on the noise-free depth (reads neighbouring rows).
cv::Mat Simulator::sensorDepth(const View& view, int index) const {
  const auto& so = options_.sensor;
  const auto& co = options_.camera;
  const int W = view.depth.cols, H = view.depth.rows;
  cv::Mat depth = cv::Mat::zeros(H, W, CV_16UC1);
  const cv::Mat shadow = projectorShadows(view.depth);
  const double cos_limit = std::cos(so.grazing_angle * M_PI / 180);
  const std::uint64_t seed = static_cast<std::uint64_t>(options_.simulator.seed);
  auto edge = [&](int u, int v, double z) {
    for (auto [du, dv] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const int uu = u + du, vv = v + dv;
      if (uu < 0 || vv < 0 || uu >= W || vv >= H) continue;
      const double zn = view.depth.at<double>(vv, uu);
      if (zn <= 0 || std::abs(zn - z) > 0.05 * z) return true;
    }
    return false;
  };
  forRowsInParallel(renderThreads(), [&](int first, int step) {
    for (int v = first; v < H; v += step)
      for (int u = 0; u < W; ++u) {
        double z = view.depth.at<double>(v, u);
        if (z <= 0 || z > so.max_range || shadow.at<std::uint8_t>(v, u)) continue;
        if (view.cosines.at<double>(v, u) < cos_limit) continue;
        if (so.edge_dropout && edge(u, v, z)) continue;
        if (so.depth_noise) {
          const std::uint64_t h = hash(seed, static_cast<std::uint64_t>(index), static_cast<std::uint64_t>(v * W + u), 2);
          z += (0.0012 + 0.0019 * (z - 0.4) * (z - 0.4)) * gaussian(h);
        }
        if (so.depth_radial_bias != 0) {
          const double x = (u - co.cx) / co.fx, y = (v - co.cy) / co.fy;
          z *= 1 + so.depth_radial_bias * (x * x + y * y);
        }
        if (!scene_->disparity_offset.empty()) z = 1.0 / (1.0 / z + scene_->disparity_offset.at<double>(v, u));
        if (so.quantize) z = 1.0 / (std::round((1.0 / z) / so.disparity_step) * so.disparity_step);
        depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::clamp(std::lround(z * 5000.0), 0L, 65535L));
      }
  });
  return depth;
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
