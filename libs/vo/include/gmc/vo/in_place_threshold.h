#pragma once
// What "in place" means for a 3-D point seen twice: within a threshold that grows with
// depth as the sensor's noise does. One definition for the background selection, the
// landmarks' evidence, the start consensus and the rejoin. No I/O.

namespace gmc::vo {

/// Thresholds deciding "in place" (the odometry's 3-D inlier threshold, [Background]
/// inlier_base and inlier_per_m2).
struct InPlaceThreshold {
  double base = 0.005;    ///< m at zero depth
  double per_m2 = 0.002;  ///< growth per depth^2
  double at(double depth) const { return base + per_m2 * depth * depth; }
};

}  // namespace gmc::vo
