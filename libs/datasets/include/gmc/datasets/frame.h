#pragma once
// One RGB-D frame as every layer above the datasets library sees it.
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gmc/gmc/types.h"

namespace gmc::datasets {

struct RgbdFrame {
  double stamp = 0;          ///< seconds (UNIX time for TUM/Bonn), exact to the microsecond
  cv::Mat rgb;               ///< CV_8UC3, BGR order (OpenCV convention)
  cv::Mat depth;             ///< CV_16UC1 raw sensor units, 0 = no reading
  double depth_units = 1.0 / 5000.0;  ///< metres per depth unit (TUM: 1/5000)
  PinholeCamera camera;      ///< intrinsics of the registered RGB-D pair
  std::string name;          ///< where it came from, for messages ("rgb/1305031102.175304.png")
  std::string sensor_label;  ///< the observation's sensorLabel (rawlogs; empty for folders)
  /// T_base_camera (optical frame) when the rawlog gives the camera a sensorPose other
  /// than the identity: the camera sits on a robot whose base is the pose's reference.
  std::optional<Isometry> base_camera;
  /// The rawlog's own observation (null for folders): filters change it in place, so a
  /// writer passes on every other field unchanged (see observationOf()).
  mrpt::obs::CObservation3DRangeScan::Ptr observation;
  /// Pixel labels read with a folder's frame (label name, CV_8UC1 mask non-zero where it
  /// applies; [Dataset] label_masks): the observation made of the frame carries them.
  std::vector<std::pair<std::string, cv::Mat>> pixel_labels;

  double depthAt(int u, int v) const { return depth.at<std::uint16_t>(v, u) * depth_units; }
};

}  // namespace gmc::datasets
