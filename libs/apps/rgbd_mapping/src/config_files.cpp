#include "gmc/apps/config_files.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "gmc/apps/app.h"
#include "gmc/apps/rgbd_mapping_app.h"
#include "gmc/config/ini.h"
#include "gmc/filters/filter.h"

namespace gmc::apps {
namespace fs = std::filesystem;

std::vector<std::string> configSearchDirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("GMC_CONFIG_DIR"); env && *env) dirs.push_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back((exe.parent_path().parent_path() / "share" / "gmc-rgbd" / "config").string());
  return dirs;
}

std::string findConfig(const std::string& name_or_path) {
  if (fs::is_regular_file(name_or_path)) return name_or_path;
  const fs::path name(name_or_path);
  std::string searched;
  if (!name.is_absolute() && name_or_path.rfind("./", 0) != 0) {
    for (const auto& dir : configSearchDirs()) {
      for (const auto& candidate : {fs::path(dir) / (name_or_path + ".ini"), fs::path(dir) / name})
        if (fs::is_regular_file(candidate)) return candidate.string();
      searched += (searched.empty() ? "" : ", ") + dir;
    }
  }
  throw AppError(name_or_path + ": no such configuration file" +
                 (searched.empty() ? "" : " (nor a shipped one in " + searched + ")"));
}

namespace {
/// MRPT writes "key = value // comment"; config/default.ini's style is
/// "key = value            ; comment", one blank line between sections.
std::string asIniComments(const std::string& mrpt_text) {
  std::istringstream in(mrpt_text);
  std::ostringstream out;
  std::string line;
  bool blank = false;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t") == std::string::npos) {
      blank = true;
      continue;
    }
    if (blank && line[0] == '[') out << "\n";
    blank = false;
    const auto eq = line.find(" = ");
    const auto comment = eq == std::string::npos ? std::string::npos : line.find(" // ", eq);
    if (comment == std::string::npos) {
      out << line << "\n";
      continue;
    }
    std::string setting = line.substr(0, comment);
    setting.erase(setting.find_last_not_of(' ') + 1);
    out << std::left << std::setw(28) << setting << " ; " << line.substr(comment + 4) << "\n";
  }
  return out.str();
}
}  // namespace

InvocationPaths invocationPaths(const std::vector<std::string>& positional,
                                const std::string& config_option, bool print_config) {
  InvocationPaths p;
  const size_t inputs = print_config ? 0 : 1;  // --print-config needs no input
  std::string config = config_option;
  if (positional.size() == inputs + 1 && config.empty()) {
    config = positional.front();
  } else if (positional.size() == inputs + 1) {
    p.error = "the configuration is given twice (" + positional.front() + " and --config)";
  } else if (positional.size() != inputs) {
    p.error = print_config ? "--print-config takes at most a configuration"
                           : "expected [<config.ini>] <input>";
  }
  if (!p.error.empty()) return p;
  p.config = findConfig(config.empty() ? "default" : config);
  if (inputs) p.input = positional.back();
  return p;
}

std::string effectiveConfigText(const std::string& config_path, const std::vector<std::string>& overrides) {
  auto ini = cfg::loadIniFile(config_path);
  cfg::applyOverrides(ini, overrides);
  PipelineConfig config = loadPipelineConfig(ini, config_path);
  mrpt::config::CConfigFileMemory out;
  cfg::saveSection(out, "Dataset", config.dataset);
  cfg::saveSection(out, "Playback", config.playback);
  cfg::saveSection(out, "Output", config.output);
  cfg::saveSection(out, "Mapping", config.map);
  filters::saveFilterSettings(ini, config_path, out);
  std::string text;
  out.getContent(text);
  return "; effective configuration of " + config_path + "\n" + asIniComments(text);
}

int printEffectiveConfig(const std::string& config_path, const std::vector<std::string>& overrides) {
  std::cout << effectiveConfigText(config_path, overrides);
  return 0;
}

}  // namespace gmc::apps
