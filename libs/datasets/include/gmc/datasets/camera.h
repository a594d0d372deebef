#pragma once
#include <string>

#include "gmc/gmc/types.h"

namespace gmc::datasets {

/// "fr1", "fr2", "fr3", "bonn" (published pinhole intrinsics, 640x480) or
/// "fx,fy,cx,cy". Throws std::invalid_argument naming the bad value.
PinholeCamera cameraPreset(const std::string& name_or_values);

}  // namespace gmc::datasets
