// INI loading into every option struct, as the apps do it: loadIniFile() on a file,
// --set overrides, loadSection() per section (strict: unknown keys, malformed and
// out-of-range values are errors). Input: the INI text, then optionally a NUL byte and
// one "Section.key=value" override per line. Documented failure: gmc::cfg::ConfigError.
// A struct that loads must also survive saveSection() -> loadSection() unchanged.
#include <sstream>

#include "fuzz_util.h"
#include "gmc/apps/rgbd_mapping_app.h"
#include "gmc/config/ini.h"
#include "gmc/filters/gmc_filter.h"
#include "gmc/gmc/gmc.h"
#include "gmc/gmc/gms.h"
#include "gmc/mapping/static_map.h"
#include "gmc/sim/simulator.h"
#include "gmc/vo/dynamic_mask.h"
#include "gmc/vo/odometry.h"
#include "gmc/vo/pose_refinement.h"

namespace {

namespace cfg = gmc::cfg;


template <class Options>
std::string asText(const std::string& section, Options& options) {
  mrpt::config::CConfigFileMemory out;
  cfg::saveSection(out, section, options);
  return out.getContent();
}

/// Loads [section]; when it loads, what saveSection() writes must load back the same.
template <class Options>
void loadAndRoundTrip(const mrpt::config::CConfigFileBase& ini, const std::string& section) {
  Options options;
  try {
    cfg::loadSection(ini, section, options, "fuzz.ini");
  } catch (const cfg::ConfigError&) {
    return;
  }
  const std::string first = asText(section, options);
  mrpt::config::CConfigFileMemory reread(first);
  Options again;
  try {
    cfg::loadSection(reread, section, again, "saved.ini");
  } catch (const cfg::ConfigError& e) {
    std::fprintf(stderr, "saved section does not load: %s\n%s\n", e.what(), first.c_str());
    std::abort();
  }
  if (asText(section, again) != first) {
    std::fprintf(stderr, "round trip changed [%s]:\n%s\n---\n%s\n", section.c_str(), first.c_str(),
                 asText(section, again).c_str());
    std::abort();
  }
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) out.push_back(line);
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = gmc::fuzz::scratchPath("fuzz.ini");
  const auto [text, overrides] = gmc::fuzz::splitAtNul(data, size);
  gmc::fuzz::writeFile(path, text.data(), text.size());
  mrpt::config::CConfigFileMemory ini;
  try {
    ini = cfg::loadIniFile(path);
    cfg::applyOverrides(ini, lines(overrides));
  } catch (const cfg::ConfigError&) {
    return 0;
  }
  loadAndRoundTrip<gmc::GmcParams>(ini, "GMC");
  loadAndRoundTrip<gmc::GmsParams>(ini, "GMS");
  loadAndRoundTrip<gmc::features::FrontendOptions>(ini, "Frontend");
  loadAndRoundTrip<gmc::vo::OdometryOptions>(ini, "Odometry");
  loadAndRoundTrip<gmc::vo::RefinementOptions>(ini, "Refinement");
  loadAndRoundTrip<gmc::vo::DynamicMaskOptions>(ini, "DynamicMask");
  loadAndRoundTrip<gmc::filters::GmcFilterOptions>(ini, "GmcFilter");
  loadAndRoundTrip<gmc::filters::DepthRangeFilter::Options>(ini, "DepthRange");
  loadAndRoundTrip<gmc::filters::DecimateFilter::Options>(ini, "Decimate");
  loadAndRoundTrip<gmc::mapping::StaticMapOptions>(ini, "Mapping");
  loadAndRoundTrip<gmc::apps::DatasetOptions>(ini, "Dataset");
  loadAndRoundTrip<gmc::apps::PlaybackOptions>(ini, "Playback");
  loadAndRoundTrip<gmc::apps::OutputOptions>(ini, "Output");
  loadAndRoundTrip<gmc::sim::SimulatorOptions>(ini, "Simulator");
  loadAndRoundTrip<gmc::sim::CameraOptions>(ini, "Camera");
  loadAndRoundTrip<gmc::sim::TrajectoryOptions>(ini, "Trajectory");
  loadAndRoundTrip<gmc::sim::PeopleOptions>(ini, "People");
  loadAndRoundTrip<gmc::sim::SensorOptions>(ini, "Sensor");
  return 0;
}
