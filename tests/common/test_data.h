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

/// Where tests write: build/test_scratch next to the test binaries (build/bin), so that
/// two checkouts testing on one machine at once do not remove each other's folders (a
/// shared /tmp/gmc_test_* did); the system's temporary folder if the binary is unknown.
inline std::filesystem::path scratchRoot() {
  std::error_code error;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error || exe.empty()) return std::filesystem::temp_directory_path();
  return exe.parent_path().parent_path() / "test_scratch";
}

/// A fresh empty folder under the build tree for one test's outputs.
inline std::string scratchDir(const std::string& name) {
  const auto p = scratchRoot() / ("gmc_test_" + name);
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

}  // namespace gmc::testdata

#define GMC_REQUIRE_DATA(var, sub)                                                     \
  const std::string var = gmc::testdata::dataDir(sub);                                 \
  if (var.empty()) GTEST_SKIP() << "GMC_DATA_DIR not set or " << sub << " missing: "    \
                                << "set GMC_DATA_DIR=../shared/data to run this test"
