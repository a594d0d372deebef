// TUM file lists (rgb.txt, depth.txt) and their association, as a TUM folder is opened.
// Input: rgb.txt, a NUL byte, depth.txt (without a NUL both lists are the same text).
// Documented failure: gmc::datasets::InputError. Anything else is a finding.
#include <cmath>
#include <filesystem>
#include <set>

#include "fuzz_util.h"
#include "gmc/datasets/tum.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace ds = gmc::datasets;
  static const std::string dir = [] {
    const auto d = gmc::fuzz::scratchPath("tum");
    std::filesystem::create_directories(d);
    return d;
  }();
  auto [rgb, depth] = gmc::fuzz::splitAtNul(data, size);
  if (depth.empty()) depth = rgb;
  gmc::fuzz::writeFile(dir + "/rgb.txt", rgb.data(), rgb.size());
  gmc::fuzz::writeFile(dir + "/depth.txt", depth.data(), depth.size());
  try {
    const auto list = ds::readTumList(dir + "/rgb.txt");
    for (size_t i = 0; i < list.size(); ++i) {
      GMC_FUZZ_CHECK(std::isfinite(list[i].stamp));
      GMC_FUZZ_CHECK(!list[i].path.empty());
      GMC_FUZZ_CHECK(i == 0 || list[i].stamp >= list[i - 1].stamp);
    }
    const auto pairs = ds::pairTumFolder(dir);
    GMC_FUZZ_CHECK(pairs.pairs.size() + pairs.unpaired_rgb.size() == list.size());
    std::set<size_t> rgb_lines, depth_lines;
    for (const auto& [r, d] : pairs.pairs) {
      GMC_FUZZ_CHECK(std::abs(r.stamp - d.stamp) < 0.02);
      GMC_FUZZ_CHECK(rgb_lines.insert(r.line).second);  // each frame used once
      GMC_FUZZ_CHECK(depth_lines.insert(d.line).second);
    }
    for (size_t i = 1; i < pairs.pairs.size(); ++i)
      GMC_FUZZ_CHECK(pairs.pairs[i].first.stamp >= pairs.pairs[i - 1].first.stamp);
  } catch (const ds::InputError&) {
  }
  return 0;
}
