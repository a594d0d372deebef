#pragma once
// MRPT observation filters, configured from INI and chained (the style of mp2p_icp's
// filters: a filter initialises from its own section and filters one thing; a registry
// creates them by name; the chain is checked when it is built):
//
//   [Filters]
//   chain = depth_range, decimate, decimate@DecimateMore, gmc   ; left to right
//   sensor_label = XTION_FRONT   ; cameras filtered (empty = every RGB-D scan)
//
// "name" reads the filter's default section ([Decimate]); "name@Section" reads
// [Section], so one filter can appear twice with different settings.
#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <opencv2/core.hpp>

#include <any>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace gmc::filters {

/// What filters learn about the current frame, for later filters and the stages after
/// the chain: named products whose type their producer documents (the gmc filter's
/// "tracking" is a vo::FrameTracking), and the dynamic mask.
struct FilterContext {
  std::size_t frame_index = 0;
  cv::Mat dynamic_mask;  ///< CV_8UC1, 255 = dynamic (gmc filter)
  std::map<std::string, std::any> products;

  /// The product `name` as a T, or nullptr when no filter set it.
  template <class T>
  T* product(const std::string& name) {
    const auto it = products.find(name);
    return it == products.end() ? nullptr : std::any_cast<T>(&it->second);
  }
};

class ObservationFilter {
 public:
  virtual ~ObservationFilter() = default;
  /// The name the registry knows it by.
  virtual std::string name() const = 0;
  /// The section a chain entry without "@Section" reads.
  virtual std::string defaultSection() const = 0;
  /// Reads [section] (and any shared sections it needs); unknown keys are errors.
  virtual void initialize(const mrpt::config::CConfigFileBase& ini, const std::string& section,
                          const std::string& source) = 0;
  /// Every INI section this filter reads when initialised from `section`.
  virtual std::vector<std::string> sections(const std::string& section) const { return {section}; }
  /// Context products this filter sets, and those it needs from an earlier filter.
  virtual std::vector<std::string> provides() const { return {}; }
  virtual std::vector<std::string> needs() const { return {}; }
  /// Writes the settings initialize() read, each key with its comment (--print-config).
  virtual void save(mrpt::config::CConfigFileBase& /*out*/, const std::string& /*section*/) const {}
  /// Returns false to drop the observation.
  virtual bool filter(mrpt::obs::CObservation3DRangeScan& obs, FilterContext& context) = 0;
  /// The input has ended: a filter that holds results back gives them as products of
  /// `context` (the gmc filter: kFinalRevisions). Most filters hold nothing.
  virtual void finish(FilterContext& /*context*/) {}
};

using FilterChain = std::vector<std::unique_ptr<ObservationFilter>>;
using FilterFactory = std::function<std::unique_ptr<ObservationFilter>()>;

/// Adds a filter type to the registry (from any library or program, e.g. at static
/// initialisation: `const bool registered = registerFilter("blur", [] {...});`).
/// Throws std::invalid_argument when the name is taken. Returns true.
bool registerFilter(const std::string& name, FilterFactory factory);
/// Filter names known to the registry, sorted ("decimate", "depth_range", "gmc", ...).
std::vector<std::string> availableFilters();
/// Throws std::invalid_argument naming the filter when it is unknown.
std::unique_ptr<ObservationFilter> createFilter(const std::string& name);

/// [Filters] section.
struct ChainOptions {
  std::string chain = "gmc";
  std::string sensor_label;
  template <class V>
  void visit(V& v) {
    v("chain", chain,
      "comma-separated filters, applied left to right; 'name@Section' reads [Section]");
    v("sensor_label", sensor_label,
      "comma-separated sensorLabels of the RGB-D cameras to filter (empty = every camera; "
      "gmc-rgbd-mapping tracks the first, or the first camera in the input)");
  }
};
ChainOptions loadChainOptions(const mrpt::config::CConfigFileBase& ini, const std::string& source);

/// Builds the chain listed in [Filters] chain, initialising each filter, and checks it
/// before anything runs: each filter's needs are provided by an earlier one, and the
/// chain provides every product in `required` (what the caller reads after the chain,
/// e.g. {kTracking} for the odometry). Throws cfg::ConfigError naming the file and entry.
FilterChain buildChain(const mrpt::config::CConfigFileBase& ini, const std::string& source,
                       const std::vector<std::string>& required = {});

/// Every INI section the filters may read from `ini`: [Filters], each registered
/// filter's default sections, and the sections of the chain's "name@Section" entries.
std::vector<std::string> filterSections(const mrpt::config::CConfigFileBase& ini,
                                        const std::string& source);

/// Writes [Filters] and the effective settings of every registered filter's default
/// sections and of the chain's "name@Section" entries, as read from `ini`.
void saveFilterSettings(const mrpt::config::CConfigFileBase& ini, const std::string& source,
                        mrpt::config::CConfigFileBase& out);

/// Applies the chain in order; false as soon as a filter drops the observation.
bool applyChain(FilterChain& chain, mrpt::obs::CObservation3DRangeScan& obs, FilterContext& context);

/// Ends the input for every filter of the chain, in order (after the last applyChain).
void finishChain(FilterChain& chain, FilterContext& context);

/// Name of the pixel label the gmc filter writes into CObservation3DRangeScan::pixelLabels.
inline constexpr const char* kDynamicLabel = "dynamic";
/// Context product of the gmc filter: the frame's vo::FrameTracking.
inline constexpr const char* kTracking = "tracking";
/// Product of the gmc filter's finish(): the trajectory's revisions it held back at the
/// input's end (a std::vector<vo::RevisedPose>: the last frames' smoothed poses).
inline constexpr const char* kFinalRevisions = "final_revisions";

}  // namespace gmc::filters
