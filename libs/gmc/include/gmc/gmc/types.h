#pragma once
// Plain types shared by the GMC core and the layers above it. Camera frames are
// optical frames: x right, y down, z forward (TUM convention).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace gmc {

/// Pinhole intrinsics of a registered RGB-D camera (no distortion).
struct PinholeCamera {
  double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;  // TUM fr3 defaults
  int width = 640, height = 480;

  Eigen::Vector3d unproject(double u, double v, double depth) const {
    return {(u - cx) * depth / fx, (v - cy) * depth / fy, depth};
  }
  /// Pixel of a point in this camera's optical frame (z must be > 0).
  Eigen::Vector2d project(const Eigen::Vector3d& p) const {
    return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
  }
  bool inside(double u, double v) const {
    return u >= 0 && v >= 0 && u < width && v < height;
  }
};

/// Rigid transform as used across the project: T_a_b maps points of frame b into frame a.
using Isometry = Eigen::Isometry3d;

}  // namespace gmc
