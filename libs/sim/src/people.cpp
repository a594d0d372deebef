#include "people.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace gmc::sim::detail {
namespace {

constexpr double kStride = 1.4;  ///< m per gait cycle (two steps)

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

/// Direction in the walking plane at `angle` from straight down (positive = forward).
Eigen::Vector3d limb(const Eigen::Vector3d& fwd, double angle) {
  return std::sin(angle) * fwd - std::cos(angle) * Eigen::Vector3d::UnitZ();
}

void poseSeated(const Person& person, double time, std::vector<Primitive>& out) {
  const double k = person.height / 1.75;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
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
}

}  // namespace

PathState pathState(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double speed, double offset,
                    double time, double pause, double stop) {
  const Eigen::Vector2d span = to - from;
  const double L = std::max(span.norm(), 1e-9);
  PathState s;
  if (pause <= 0) {  // a walker that never stops: its clock is the distance walked
    const double walked = offset + speed * time, d = std::fmod(walked, 2 * L);
    const bool outward = d < L;
    s.at = from + span * ((outward ? d : 2 * L - d) / L);
    s.heading = span.normalized() * (outward ? 1.0 : -1.0);
    s.walked = walked;
    return s;
  }
  // A stop inserts `pause` seconds at the stop point of every pass (each way), the gait phase held meanwhile.
  const double v = std::max(speed, 1e-9);
  const double leg = L / v + pause;
  const double clock = offset / v + time;
  const double cycles = std::floor(clock / (2 * leg));
  double in_cycle = clock - cycles * 2 * leg;
  const bool outward = in_cycle < leg;
  if (!outward) in_cycle -= leg;
  const double to_stop = (outward ? stop : 1 - stop) * L / v;
  const double walking = in_cycle < to_stop ? in_cycle : in_cycle < to_stop + pause ? to_stop : in_cycle - pause;
  if (in_cycle >= to_stop && in_cycle < to_stop + pause) {
    s.standing = in_cycle - to_stop;
    s.stand_left = to_stop + pause - in_cycle;
  }
  const double d = std::min(L, speed * walking);  // along this pass
  s.at = outward ? Eigen::Vector2d(from + span * (d / L)) : Eigen::Vector2d(to - span * (d / L));
  s.heading = span.normalized() * (outward ? 1.0 : -1.0);
  s.walked = cycles * 2 * L + (outward ? d : L + d);
  return s;
}

PathState personState(const Person& person, const PathState& camera_walk, double time) {
  if (!person.with_camera)
    return pathState(person.from, person.to, person.speed, person.offset, time, person.pause, person.stop);
  PathState s = camera_walk;
  s.at += person.camera_offset;
  s.walked += person.offset;  // own gait phase, same speed
  return s;
}

void posePerson(const Person& person, const PathState& state, double time, bool articulated,
                std::vector<Primitive>& out, bool fidget) {
  if (person.sitting) return poseSeated(person, time, out);
  const double k = person.height / 1.75;
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  Eigen::Vector2d heading = state.heading;
  Eigen::Vector3d lean = Eigen::Vector3d::Zero();
  double gesture = 0;
  if (fidget && state.standing >= 0) {
    // Eased in and out over a second: the stand starts and ends at walking pose. The
    // turn (+-25 deg, 5 s) moves the shoulders up to 5 mm per frame, the weight shift
    // (+-5 cm, 3 s) the torso 3 mm, the gesturing forearm 1-2 cm.
    const double ease = std::min({1.0, state.standing, state.stand_left});
    const double phase = person.offset * 7.3;  // each person fidgets in its own rhythm
    const double yaw = ease * 0.44 * std::sin(2 * M_PI * time / 5.0 + phase);
    heading = Eigen::Rotation2Dd(yaw) * heading;
    const Eigen::Vector2d across(-heading.y(), heading.x());
    const double shift = ease * 0.05 * std::sin(2 * M_PI * time / 3.1 + 1.7 * phase);
    lean = Eigen::Vector3d(across.x(), across.y(), 0) * shift;
    gesture = ease * (0.5 + 0.5 * std::sin(2 * M_PI * time / 1.9 + phase));
  }
  const Eigen::Vector3d feet(state.at.x(), state.at.y(), 0), fwd(heading.x(), heading.y(), 0),
      side(-heading.y(), heading.x(), 0);
  const double phase = 2 * M_PI * state.walked / kStride;
  const double swing = 0.45 * std::sin(phase);
  addCapsule(out, feet + 1.0 * k * up + lean, feet + 1.42 * k * up + lean, 0.19, person.top);
  addHead(out, feet + 1.63 * k * up + 1.1 * lean, person.skin);
  for (int s : {-1, 1}) {
    const double a = s * swing;
    const Eigen::Vector3d hip = feet + 0.92 * k * up + 0.1 * s * side + 0.8 * lean;
    const Eigen::Vector3d shoulder = feet + 1.42 * k * up + 0.26 * s * side + lean;
    if (!articulated) {
      addCapsule(out, hip, hip + 0.85 * k * limb(fwd, a), 0.08, person.bottom);
      addCapsule(out, shoulder, shoulder + 0.6 * k * limb(fwd, -a), 0.05, person.top);
      continue;
    }
    // The knee bends while the leg swings forward (up to 45 deg), the elbow 15-55 deg
    // forward with the arm's swing: silhouettes change shape, not only position.
    const double knee_flex = 0.8 * std::max(0.0, s * std::cos(phase));
    const Eigen::Vector3d knee = hip + 0.44 * k * limb(fwd, a);
    addCapsule(out, hip, knee, 0.085, person.bottom);
    addCapsule(out, knee, knee + 0.43 * k * limb(fwd, a - knee_flex), 0.065, person.bottom);
    const Eigen::Vector3d elbow = shoulder + 0.3 * k * limb(fwd, -a);
    addCapsule(out, shoulder, elbow, 0.055, person.top);
    const double lift = s > 0 ? 1.2 * gesture : 0.0;  // one hand talks while standing
    addCapsule(out, elbow, elbow + 0.28 * k * limb(fwd, -a + 0.6 + lift + 0.35 * std::sin(-s * phase)), 0.045,
               person.skin);
  }
}

}  // namespace gmc::sim::detail
