#pragma once
// Where the benchmarks find the real recordings: GMC_DATA_DIR, default ../shared/data
// (run from the repository's root). Benchmarks skip with a message when a folder is absent.
#include <cstdlib>
#include <filesystem>
#include <string>

namespace gmc::bench {

/// The folder `sub` of the shared data, or "" when it does not exist.
inline std::string sharedDataFolder(const std::string& sub) {
  const char* root = std::getenv("GMC_DATA_DIR");
  const std::filesystem::path folder = std::filesystem::path(root && *root ? root : "../shared/data") / sub;
  return std::filesystem::is_directory(folder) ? folder.string() : "";
}

}  // namespace gmc::bench
