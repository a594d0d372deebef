#pragma once
// Where gmc-rgbd-mapping's configuration comes from: a file, or one shipped in
// <prefix>/share/gmc-rgbd/config/ (found from the executable), and what it amounts to.
#include <string>
#include <vector>

namespace gmc::apps {

/// Folders searched for a configuration named without a path, in order: $GMC_CONFIG_DIR
/// when set, then <executable's folder>/../share/gmc-rgbd/config (the installed tree;
/// the build tree mirrors it).
std::vector<std::string> configSearchDirs();

/// `name_or_path` when it is a file; else "<dir>/<name>.ini" or "<dir>/<name>" in the
/// first search folder that has it ("default", "bonn", "tum_fr3", "sim/walkers_xyz").
/// Throws AppError naming the folders searched.
std::string findConfig(const std::string& name_or_path);

/// The configuration and input named on the command line: "[config] input", the config
/// possibly from --config instead, "default" when none is named. `error` says what is
/// wrong, empty when nothing is.
struct InvocationPaths {
  std::string config, input, error;
};
InvocationPaths invocationPaths(const std::vector<std::string>& positional,
                                const std::string& config_option, bool print_config);

/// Every section gmc-rgbd-mapping reads, each key with its effective value (file plus
/// overrides, defaults for keys absent) and its comment, as INI text. Throws as the app
/// would on a bad configuration.
std::string effectiveConfigText(const std::string& config_path, const std::vector<std::string>& overrides);

/// Prints effectiveConfigText() on stdout; returns 0.
int printEffectiveConfig(const std::string& config_path, const std::vector<std::string>& overrides);

}  // namespace gmc::apps
