#pragma once
// People of the scene: where they walk (back and forth along a path, or in step with the
// camera) and their body parts at a given time.
#include <Eigen/Core>

#include <vector>

#include "primitive.h"

namespace gmc::sim::detail {

/// A walker's place on its path at some time.
struct PathState {
  Eigen::Vector2d at = Eigen::Vector2d::Zero();       ///< feet (world x, y)
  Eigen::Vector2d heading = Eigen::Vector2d::UnitX(); ///< unit walking direction
  double walked = 0;                                  ///< distance walked so far (m): the gait phase
  double standing = -1;                               ///< s into a stand (-1: walking) ...
  double stand_left = 0;                              ///< ... and s until it ends
};

/// Back and forth between `from` and `to` at `speed`, starting `offset` metres along;
/// on every pass standing still for `pause` seconds at `stop` (fraction of the way from
/// `from`; 0 pause = never stops).
PathState pathState(const Eigen::Vector2d& from, const Eigen::Vector2d& to, double speed, double offset,
                    double time, double pause = 0, double stop = 0.5);

struct Person {
  Eigen::Vector2d from = Eigen::Vector2d::Zero(), to = Eigen::Vector2d::Zero();  ///< path ends
  double speed = 1, offset = 0, height = 1.75;
  double pause = 0, stop = 0.5;    ///< s standing still on every pass, where (fraction of the path)
  Material top, bottom, skin;
  bool sitting = false;
  Eigen::Vector2d seat = Eigen::Vector2d::Zero();
  bool with_camera = false;        ///< walks in step with the camera (synchronous group)
  Eigen::Vector2d camera_offset = Eigen::Vector2d::Zero();  ///< from the camera's path point
};

/// Where a walker is: its own path, or (with_camera) the camera's path state plus its offset.
PathState personState(const Person& person, const PathState& camera_walk, double time);

/// Appends the body parts of a person at `state` (seated people ignore it and use `time`).
/// articulated: legs bend at the knee and arms at the elbow, else each limb is one capsule.
/// fidget: a standing person sways, turns and gestures (centimetres per frame, as real
/// people who stop: slow enough to pass a per-frame motion test as background).
void posePerson(const Person& person, const PathState& state, double time, bool articulated,
                std::vector<Primitive>& out, bool fidget = false);

}  // namespace gmc::sim::detail
