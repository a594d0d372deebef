#include <opencv2/imgproc.hpp>

#include <chrono>
#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "gmc/config/ini.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/rawlog_stream.h"
#include "gmc/filters/gmc_filter.h"
#include "gmc/datasets/pixel_labels.h"

namespace gmc::filters {
namespace {

std::map<std::string, FilterFactory>& registry() {
  static std::map<std::string, FilterFactory> r = {
      {"gmc", [] { return std::make_unique<GmcFilter>(); }},
      {"depth_range", [] { return std::make_unique<DepthRangeFilter>(); }},
      {"decimate", [] { return std::make_unique<DecimateFilter>(); }},
  };
  return r;
}

/// "person, chair" -> {"person", "chair"}; an empty name between commas is an error.
std::vector<std::string> splitLabelNames(const std::string& text, const std::string& source,
                                         const std::string& section) {
  std::vector<std::string> names;
  if (text.find_first_not_of(" \t") == std::string::npos) return names;
  std::stringstream in(text);
  std::string name;
  while (std::getline(in, name, ',')) {
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    if (name.empty())
      throw cfg::ConfigError(source + ": [" + section + "] known_dynamic_labels: empty label name in '" + text + "'");
    names.push_back(name);
  }
  return names;
}

/// One chain entry: "name" or "name@Section".
struct ChainEntry {
  std::string text, name, section;  ///< section empty = the filter's default
};

std::vector<ChainEntry> chainEntries(const ChainOptions& options, const std::string& source) {
  std::vector<ChainEntry> entries;
  for (const auto& text : datasets::splitList(options.chain)) {
    const auto at = text.find('@');
    ChainEntry e{text, text.substr(0, at), at == std::string::npos ? "" : text.substr(at + 1)};
    if (e.name.empty() || (at != std::string::npos && e.section.empty()))
      throw cfg::ConfigError(source + ": [Filters] chain: '" + text + "' is not 'name' or 'name@Section'");
    entries.push_back(e);
  }
  return entries;
}

std::unique_ptr<ObservationFilter> createEntry(const ChainEntry& entry, const std::string& source) {
  try {
    return createFilter(entry.name);
  } catch (const std::invalid_argument& e) {
    throw cfg::ConfigError(source + ": [Filters] chain: " + e.what());
  }
}

bool contains(const std::vector<std::string>& list, const std::string& item) {
  return std::find(list.begin(), list.end(), item) != list.end();
}

/// Each filter's needs come from an earlier filter; the chain gives what the caller needs.
void checkChain(const FilterChain& chain, const std::vector<ChainEntry>& entries,
                const std::vector<std::string>& required, const std::string& source) {
  std::vector<std::string> provided;
  for (size_t i = 0; i < chain.size(); ++i) {
    for (const auto& need : chain[i]->needs())
      if (!contains(provided, need))
        throw cfg::ConfigError(source + ": [Filters] chain: '" + entries[i].text + "' needs '" +
                               need + "' from a filter before it");
    for (const auto& p : chain[i]->provides()) provided.push_back(p);
  }
  for (const auto& need : required) {
    if (contains(provided, need)) continue;
    std::string providers;
    for (const auto& name : availableFilters())
      if (contains(createFilter(name)->provides(), need)) providers += (providers.empty() ? "" : ", ") + name;
    throw cfg::ConfigError(source + ": [Filters] chain must contain a filter that provides '" +
                           need + "' (" + providers + ")");
  }
}

}  // namespace

bool registerFilter(const std::string& name, FilterFactory factory) {
  if (name.empty() || name.find_first_of("@, \t") != std::string::npos)
    throw std::invalid_argument("filter name '" + name + "' must be one word");
  if (!registry().emplace(name, std::move(factory)).second)
    throw std::invalid_argument("filter '" + name + "' is already registered");
  return true;
}

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

ChainOptions loadChainOptions(const mrpt::config::CConfigFileBase& ini, const std::string& source) {
  ChainOptions options;
  cfg::loadSection(ini, "Filters", options, source);
  return options;
}

FilterChain buildChain(const mrpt::config::CConfigFileBase& ini, const std::string& source,
                       const std::vector<std::string>& required) {
  const auto entries = chainEntries(loadChainOptions(ini, source), source);
  FilterChain chain;
  for (const auto& entry : entries) chain.push_back(createEntry(entry, source));
  checkChain(chain, entries, required, source);  // before any filter allocates its state
  for (size_t i = 0; i < chain.size(); ++i) {
    const auto& section = entries[i].section.empty() ? chain[i]->defaultSection() : entries[i].section;
    chain[i]->initialize(ini, section, source);
  }
  return chain;
}

std::vector<std::string> filterSections(const mrpt::config::CConfigFileBase& ini,
                                        const std::string& source) {
  std::vector<std::string> sections = {"Filters"};
  auto add = [&](const std::vector<std::string>& more) {
    for (const auto& s : more)
      if (!contains(sections, s)) sections.push_back(s);
  };
  for (const auto& name : availableFilters()) {
    const auto filter = createFilter(name);
    add(filter->sections(filter->defaultSection()));
  }
  for (const auto& entry : chainEntries(loadChainOptions(ini, source), source))
    if (!entry.section.empty()) add(createEntry(entry, source)->sections(entry.section));
  return sections;
}

void saveFilterSettings(const mrpt::config::CConfigFileBase& ini, const std::string& source,
                        mrpt::config::CConfigFileBase& out) {
  auto options = loadChainOptions(ini, source);
  cfg::saveSection(out, "Filters", options);
  auto saveOne = [&](const std::string& name, const std::string& section) {
    const auto filter = createFilter(name);
    filter->initialize(ini, section, source);
    filter->save(out, section);
  };
  for (const auto& name : availableFilters()) saveOne(name, createFilter(name)->defaultSection());
  for (const auto& entry : chainEntries(options, source))
    if (!entry.section.empty()) saveOne(entry.name, entry.section);
}

bool applyChain(FilterChain& chain, mrpt::obs::CObservation3DRangeScan& obs,
                FilterContext& context) {
  for (auto& f : chain)
    if (!f->filter(obs, context)) return false;
  return true;
}

void finishChain(FilterChain& chain, FilterContext& context) {
  for (auto& f : chain) f->finish(context);
}

// ---------------------------------------------------------------- gmc
std::vector<std::string> GmcFilter::sections(const std::string& section) const {
  return {section,      "Frontend",  "GMS",       "GMC",    "Odometry",
          "Refinement", "LocalMap", "Background", "Keyframes", "Window", "Rejoin", "StartConsensus", "Hindsight",
          "FreeSpace", "DepthAlignment",
          "DynamicMask"};
}

void GmcFilter::initialize(const mrpt::config::CConfigFileBase& ini, const std::string& section,
                           const std::string& source) {
  cfg::loadSection(ini, section, options_, source);
  known_dynamic_labels_ = splitLabelNames(options_.known_dynamic_labels, source, section);
  cfg::loadSection(ini, "Frontend", odometry_config_.frontend, source);
  cfg::loadSection(ini, "GMS", odometry_config_.gms, source);
  cfg::loadSection(ini, "GMC", odometry_config_.gmc, source);
  cfg::loadSection(ini, "Odometry", odometry_config_.odometry, source);
  cfg::loadSection(ini, "Refinement", odometry_config_.refinement, source);
  cfg::loadSection(ini, "LocalMap", odometry_config_.local_map, source);
  cfg::loadSection(ini, "Background", odometry_config_.background, source);
  cfg::loadSection(ini, "Keyframes", odometry_config_.keyframes, source);
  cfg::loadSection(ini, "Window", odometry_config_.window, source);
  cfg::loadSection(ini, "Rejoin", odometry_config_.rejoin, source);
  cfg::loadSection(ini, "StartConsensus", odometry_config_.start_consensus, source);
  cfg::loadSection(ini, "Hindsight", odometry_config_.hindsight, source);
  cfg::loadSection(ini, "FreeSpace", odometry_config_.free_space, source);
  cfg::loadSection(ini, "DepthAlignment", odometry_config_.depth_alignment, source);
  cfg::loadSection(ini, "DynamicMask", mask_options_, source);
  odometry_ = std::make_unique<vo::RgbdOdometry>(odometry_config_);
  // GMC off is the run without the filter (the paper's baseline): no dynamic evidence at
  // all, so the free-space check is off too.
  if (!odometry_config_.gmc.enabled) mask_options_.free_space_check = false;
  mask_builder_ = std::make_unique<vo::DynamicMaskBuilder>(mask_options_);
}

void GmcFilter::save(mrpt::config::CConfigFileBase& out, const std::string& section) const {
  // saveSection takes the structs by non-const reference (their visit() is not const).
  auto options = options_;
  auto odometry = odometry_config_;
  auto mask = mask_options_;
  cfg::saveSection(out, section, options);
  cfg::saveSection(out, "Frontend", odometry.frontend);
  cfg::saveSection(out, "GMS", odometry.gms);
  cfg::saveSection(out, "GMC", odometry.gmc);
  cfg::saveSection(out, "Odometry", odometry.odometry);
  cfg::saveSection(out, "Refinement", odometry.refinement);
  cfg::saveSection(out, "LocalMap", odometry.local_map);
  cfg::saveSection(out, "Background", odometry.background);
  cfg::saveSection(out, "Keyframes", odometry.keyframes);
  cfg::saveSection(out, "Window", odometry.window);
  cfg::saveSection(out, "Rejoin", odometry.rejoin);
  cfg::saveSection(out, "StartConsensus", odometry.start_consensus);
  cfg::saveSection(out, "Hindsight", odometry.hindsight);
  cfg::saveSection(out, "FreeSpace", odometry.free_space);
  cfg::saveSection(out, "DepthAlignment", odometry.depth_alignment);
  cfg::saveSection(out, "DynamicMask", mask);
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
  cv::Mat known_dynamic;
  if (!known_dynamic_labels_.empty()) {
    try {
      known_dynamic = datasets::pixelsLabelled(obs.pixelLabels, known_dynamic_labels_, gray.rows, gray.cols);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error("frame " + std::to_string(context.frame_index) + ": " + e.what());
    }
  }
  auto& tracking = context.products[kTracking] =
      odometry_->process(gray, frame.depth, frame.depth_units, frame.camera, frame.stamp, known_dynamic);
  auto& result = std::any_cast<vo::FrameTracking&>(tracking);
  const auto mask_start = std::chrono::steady_clock::now();
  context.dynamic_mask = mask_builder_->build(result, frame.depth, frame.depth_units, frame.camera);
  if (!known_dynamic.empty())
    context.dynamic_mask = context.dynamic_mask.empty() ? known_dynamic : (context.dynamic_mask | known_dynamic);
  odometry_->distrustMaskedLandmarks(context.dynamic_mask);
  result.times.mask =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - mask_start).count();

  const cv::Mat& mask = context.dynamic_mask;
  if (options_.write_pixel_labels) {
    // Labels the observation already carries (a recording's, an earlier stage's) stay.
    try {
      obs.pixelLabels = datasets::withLabel(obs.pixelLabels, mask, kDynamicLabel);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error("frame " + std::to_string(context.frame_index) + ": " + e.what());
    }
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

void GmcFilter::finish(FilterContext& context) {
  context.products[kFinalRevisions] = odometry_->finish();
}

// ---------------------------------------------------------------- depth_range
void DepthRangeFilter::initialize(const mrpt::config::CConfigFileBase& ini,
                                  const std::string& section, const std::string& source) {
  cfg::loadSection(ini, section, options_, source);
  if (options_.min_depth >= options_.max_depth)
    throw cfg::ConfigError(source + ": [" + section + "] min_depth must be below max_depth");
}

void DepthRangeFilter::save(mrpt::config::CConfigFileBase& out, const std::string& section) const {
  auto copy = options_;
  cfg::saveSection(out, section, copy);
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
                                const std::string& section, const std::string& source) {
  cfg::loadSection(ini, section, options_, source);
}

void DecimateFilter::save(mrpt::config::CConfigFileBase& out, const std::string& section) const {
  auto copy = options_;
  cfg::saveSection(out, section, copy);
}

bool DecimateFilter::filter(mrpt::obs::CObservation3DRangeScan&, FilterContext&) {
  return (seen_++ % static_cast<std::size_t>(options_.keep_every)) == 0;
}

}  // namespace gmc::filters
