#pragma once
// MRPT observation filters, configured from INI and chained:
//
//   [Filters]
//   chain = depth_range, gmc      ; applied left to right
//
// A filter is two methods (mp2p_icp style): initialize from its INI section, and
// filter one observation (changing it, or dropping it by returning false).
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <opencv2/core.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gmc/vo/odometry.h"

namespace gmc::filters {

/// What filters learn about the current frame, for the stages after the chain.
struct FilterContext {
  std::size_t frame_index = 0;
  std::optional<vo::FrameTracking> tracking;  ///< set by the gmc filter
  cv::Mat dynamic_mask;                       ///< CV_8UC1, 255 = dynamic (gmc filter)
};

class ObservationFilter {
 public:
  virtual ~ObservationFilter() = default;
  virtual std::string name() const = 0;
  /// Reads the filter's own INI section(s); unknown keys are errors.
  virtual void initialize(const mrpt::config::CConfigFileBase& ini, const std::string& source) = 0;
  /// Returns false to drop the observation.
  virtual bool filter(mrpt::obs::CObservation3DRangeScan& obs, FilterContext& context) = 0;
};

using FilterChain = std::vector<std::unique_ptr<ObservationFilter>>;

/// Filter names known to the factory: "gmc", "depth_range", "decimate".
std::vector<std::string> availableFilters();
/// Throws std::invalid_argument naming the filter when it is unknown.
std::unique_ptr<ObservationFilter> createFilter(const std::string& name);

/// Builds the chain listed in [Filters] chain (strict section), initialising each filter.
FilterChain buildChain(const mrpt::config::CConfigFileBase& ini, const std::string& source);

/// Applies the chain in order; false as soon as a filter drops the observation.
bool applyChain(FilterChain& chain, mrpt::obs::CObservation3DRangeScan& obs, FilterContext& context);

/// Name of the pixel label the gmc filter writes into CObservation3DRangeScan::pixelLabels.
inline constexpr const char* kDynamicLabel = "dynamic";

}  // namespace gmc::filters
