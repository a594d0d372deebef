#pragma once
#include <string>

#include "gmc/gmc/types.h"

namespace gmc::datasets {

/// "fr1", "fr2", "fr3", "bonn" (published pinhole intrinsics, 640x480) or
/// "fx,fy,cx,cy". Throws std::invalid_argument naming the bad value.
PinholeCamera cameraPreset(const std::string& name_or_values);

/// Radial-tangential lens distortion (OpenCV's and TUM's order k1, k2, p1, p2, k3).
struct LensDistortion {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  bool none() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0; }
};

/// The distortion TUM publishes for a preset's camera: "fr1" (0.2624, -0.9531, -0.0054,
/// 0.0026, 1.1633), "fr2" (0.2312, -0.7849, -0.0033, -0.0001, 0.9172); none for "fr3"
/// (TUM publishes zero), "bonn" (its published pinhole model) and explicit intrinsics.
LensDistortion presetDistortion(const std::string& name_or_values);

}  // namespace gmc::datasets
