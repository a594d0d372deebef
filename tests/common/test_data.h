#pragma once
// Where the real recordings are: GMC_DATA_DIR (../shared/data in CI). Tests that need
// them skip with a message when it is not set or a folder is missing.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace gmc::testdata {

inline std::string dataDir(const std::string& sub) {
  const char* root = std::getenv("GMC_DATA_DIR");
  if (!root || !*root) return "";
  const auto p = std::filesystem::path(root) / sub;
  return std::filesystem::exists(p) ? p.string() : "";
}

/// A fresh empty folder under the build tree for one test's outputs.
inline std::string scratchDir(const std::string& name) {
  const auto p = std::filesystem::temp_directory_path() / ("gmc_test_" + name);
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

}  // namespace gmc::testdata

#define GMC_REQUIRE_DATA(var, sub)                                                     \
  const std::string var = gmc::testdata::dataDir(sub);                                 \
  if (var.empty()) GTEST_SKIP() << "GMC_DATA_DIR not set or " << sub << " missing: "    \
                                << "set GMC_DATA_DIR=../shared/data to run this test"
