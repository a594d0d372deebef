#pragma once
// One RGB-D frame as every layer above the datasets library sees it.
#include <opencv2/core.hpp>
#include <string>

#include "gmc/gmc/types.h"

namespace gmc::datasets {

struct RgbdFrame {
  double stamp = 0;          ///< seconds (UNIX time for TUM/Bonn), exact to the microsecond
  cv::Mat rgb;               ///< CV_8UC3, BGR order (OpenCV convention)
  cv::Mat depth;             ///< CV_16UC1 raw sensor units, 0 = no reading
  double depth_units = 1.0 / 5000.0;  ///< metres per depth unit (TUM: 1/5000)
  PinholeCamera camera;      ///< intrinsics of the registered RGB-D pair
  std::string name;          ///< where it came from, for messages ("rgb/1305031102.175304.png")

  double depthAt(int u, int v) const { return depth.at<std::uint16_t>(v, u) * depth_units; }
};

}  // namespace gmc::datasets
