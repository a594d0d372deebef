#include <mrpt/math/CMatrixDynamic.h>  // TPixelLabelInfo.h uses it without including it
#include <mrpt/obs/TPixelLabelInfo.h>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>

#include "gmc/config/ini.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/filters/gmc_filter.h"

namespace gmc::filters {
namespace {

using Factory = std::function<std::unique_ptr<ObservationFilter>()>;

const std::map<std::string, Factory>& registry() {
  static const std::map<std::string, Factory> r = {
      {"gmc", [] { return std::make_unique<GmcFilter>(); }},
      {"depth_range", [] { return std::make_unique<DepthRangeFilter>(); }},
      {"decimate", [] { return std::make_unique<DecimateFilter>(); }},
  };
  return r;
}

/// [Filters] section: only the chain list.
struct ChainOptions {
  std::string chain = "gmc";
  template <class V>
  void visit(V& v) { v("chain", chain, "comma-separated filters, applied left to right"); }
};

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

}  // namespace

std::vector<std::string> availableFilters() {
  std::vector<std::string> names;
  for (const auto& [name, factory] : registry()) names.push_back(name);
  return names;
}

std::unique_ptr<ObservationFilter> createFilter(const std::string& name) {
  const auto it = registry().find(name);
  if (it == registry().end()) {
    std::string known;
    for (const auto& n : availableFilters()) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown filter '" + name + "' (known: " + known + ")");
  }
  return it->second();
}

FilterChain buildChain(const mrpt::config::CConfigFileBase& ini, const std::string& source) {
  ChainOptions options;
  cfg::loadSection(ini, "Filters", options, source);
  FilterChain chain;
  for (const auto& name : splitList(options.chain)) {
    std::unique_ptr<ObservationFilter> f;
    try {
      f = createFilter(name);
    } catch (const std::invalid_argument& e) {
      throw cfg::ConfigError(source + ": [Filters] chain: " + e.what());
    }
    f->initialize(ini, source);
    chain.push_back(std::move(f));
  }
  return chain;
}

bool applyChain(FilterChain& chain, mrpt::obs::CObservation3DRangeScan& obs,
                FilterContext& context) {
  for (auto& f : chain)
    if (!f->filter(obs, context)) return false;
  return true;
}

// ---------------------------------------------------------------- gmc
void GmcFilter::initialize(const mrpt::config::CConfigFileBase& ini, const std::string& source) {
  cfg::loadSection(ini, "GmcFilter", options_, source);
  cfg::loadSection(ini, "Frontend", odometry_config_.frontend, source);
  cfg::loadSection(ini, "GMS", odometry_config_.gms, source);
  cfg::loadSection(ini, "GMC", odometry_config_.gmc, source);
  cfg::loadSection(ini, "Odometry", odometry_config_.odometry, source);
  cfg::loadSection(ini, "Refinement", odometry_config_.refinement, source);
  cfg::loadSection(ini, "LocalMap", odometry_config_.local_map, source);
  cfg::loadSection(ini, "Background", odometry_config_.background, source);
  cfg::loadSection(ini, "Keyframes", odometry_config_.keyframes, source);
  cfg::loadSection(ini, "Window", odometry_config_.window, source);
  cfg::loadSection(ini, "DynamicMask", mask_options_, source);
  odometry_ = std::make_unique<vo::RgbdOdometry>(odometry_config_);
  // GMC off is the run without the filter (the paper's baseline): no dynamic evidence at
  // all, so the free-space check is off too.
  if (!odometry_config_.gmc.enabled) mask_options_.free_space_check = false;
  mask_builder_ = std::make_unique<vo::DynamicMaskBuilder>(mask_options_);
}

bool GmcFilter::filter(mrpt::obs::CObservation3DRangeScan& obs, FilterContext& context) {
  if (!obs.hasRangeImage || !obs.hasIntensityImage)
    throw std::runtime_error("frame " + std::to_string(context.frame_index) +
                             ": observation has no " +
                             (obs.hasRangeImage ? "intensity image" : "depth"));
  const datasets::RgbdFrame frame = datasets::fromObservation(obs);
  cv::Mat gray;
  if (frame.rgb.channels() == 3)
    cv::cvtColor(frame.rgb, gray, cv::COLOR_BGR2GRAY);
  else
    gray = frame.rgb;
  context.tracking =
      odometry_->process(gray, frame.depth, frame.depth_units, frame.camera, frame.stamp);
  const auto mask_start = std::chrono::steady_clock::now();
  context.dynamic_mask =
      mask_builder_->build(*context.tracking, frame.depth, frame.depth_units, frame.camera);
  context.tracking->times.mask =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - mask_start).count();

  const cv::Mat& mask = context.dynamic_mask;
  if (options_.write_pixel_labels) {
    auto labels = std::make_shared<mrpt::obs::TPixelLabelInfo<1>>();
    labels->setSize(mask.rows, mask.cols);
    labels->setLabelName(0, kDynamicLabel);
    for (int r = 0; r < mask.rows; ++r) {
      const auto* row = mask.ptr<std::uint8_t>(r);
      for (int c = 0; c < mask.cols; ++c)
        if (row[c]) labels->setLabel(r, c, 0);
    }
    obs.pixelLabels = labels;
  }
  if (options_.zero_dynamic_depth) {
    for (int r = 0; r < mask.rows && r < static_cast<int>(obs.rangeImage.rows()); ++r) {
      const auto* row = mask.ptr<std::uint8_t>(r);
      for (int c = 0; c < mask.cols && c < static_cast<int>(obs.rangeImage.cols()); ++c)
        if (row[c]) obs.rangeImage(r, c) = 0;
    }
  }
  return true;
}

// ---------------------------------------------------------------- depth_range
void DepthRangeFilter::initialize(const mrpt::config::CConfigFileBase& ini,
                                  const std::string& source) {
  cfg::loadSection(ini, "DepthRange", options_, source);
  if (options_.min_depth >= options_.max_depth)
    throw cfg::ConfigError(source + ": [DepthRange] min_depth must be below max_depth");
}

bool DepthRangeFilter::filter(mrpt::obs::CObservation3DRangeScan& obs, FilterContext&) {
  if (!obs.hasRangeImage) return true;
  const double units = obs.rangeUnits;
  for (int r = 0; r < static_cast<int>(obs.rangeImage.rows()); ++r)
    for (int c = 0; c < static_cast<int>(obs.rangeImage.cols()); ++c) {
      auto& raw = obs.rangeImage(r, c);
      const double z = raw * units;
      if (raw != 0 && (z < options_.min_depth || z > options_.max_depth)) raw = 0;
    }
  return true;
}

// ---------------------------------------------------------------- decimate
void DecimateFilter::initialize(const mrpt::config::CConfigFileBase& ini,
                                const std::string& source) {
  cfg::loadSection(ini, "Decimate", options_, source);
}

bool DecimateFilter::filter(mrpt::obs::CObservation3DRangeScan&, FilterContext&) {
  return (seen_++ % static_cast<std::size_t>(options_.keep_every)) == 0;
}

}  // namespace gmc::filters
