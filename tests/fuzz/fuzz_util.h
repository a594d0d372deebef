#pragma once
// Helpers shared by the fuzz targets: a per-process scratch path for parsers that take a
// file name, and a loud failure for broken invariants (libFuzzer records the input).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace gmc::fuzz {

/// /tmp/gmc_fuzz_<pid>_<name>: stable within one fuzzing process, distinct across jobs.
inline std::string scratchPath(const std::string& name) {
  return "/tmp/gmc_fuzz_" + std::to_string(getpid()) + "_" + name;
}

inline void writeFile(const std::string& path, const char* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(data, static_cast<std::streamsize>(size));
}

/// Splits the input at the first NUL byte: (before, after); after is empty without one.
inline std::pair<std::string, std::string> splitAtNul(const uint8_t* data, size_t size) {
  const std::string all(reinterpret_cast<const char*>(data), size);
  const auto nul = all.find('\0');
  if (nul == std::string::npos) return {all, ""};
  return {all.substr(0, nul), all.substr(nul + 1)};
}

[[noreturn]] inline void invariantBroken(const char* what) {
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what);
  std::abort();
}

#define GMC_FUZZ_CHECK(cond) \
  do {                       \
    if (!(cond)) gmc::fuzz::invariantBroken(#cond); \
  } while (0)

}  // namespace gmc::fuzz
