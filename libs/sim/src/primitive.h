#pragma once
// The renderer's analytic shapes: boxes (the room, furniture), spheres and capsules (people).
#include <Eigen/Core>

#include <cstdint>

#include "texture.h"

namespace gmc::sim::detail {

enum class Shape : std::uint8_t { Box, Sphere, Capsule };

struct Primitive {
  Shape shape = Shape::Box;
  bool inside = false;       ///< the room: rays hit its far faces
  bool dynamic = false;      ///< part of a person
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();  ///< box min/max; sphere centre (a); capsule ends
  double radius = 0;
  Material material;         ///< boxes: reseeded per face; the room: per-face materials of the scene
};

}  // namespace gmc::sim::detail
