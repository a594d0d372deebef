// The rawlog reading path of every app: openRgbdSource() on a ".rawlog" file holding the
// fuzz bytes (gzip or plain), then next() to the end. Documented failures:
// gmc::datasets::InputError (the file cannot be read as a whole) and FrameReadError (one
// frame is bad, reading goes on). Anything else is a finding, and so is a frame that
// breaks RgbdFrame's contract.
#include <cmath>

#include "fuzz_util.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace ds = gmc::datasets;
  static const std::string path = gmc::fuzz::scratchPath("in.rawlog");
  gmc::fuzz::writeFile(path, reinterpret_cast<const char*>(data), size);
  try {
    auto source = ds::openRgbdSource(path, {});
    ds::RgbdFrame frame;
    for (int calls = 0;; ++calls) {
      GMC_FUZZ_CHECK(calls < 100000);  // next() must reach the end
      try {
        if (!source->next(frame)) break;
      } catch (const ds::FrameReadError&) {
        continue;
      }
      GMC_FUZZ_CHECK(frame.rgb.type() == CV_8UC3);
      GMC_FUZZ_CHECK(frame.depth.type() == CV_16UC1);
      GMC_FUZZ_CHECK(!frame.depth.empty() && frame.depth.size() == frame.rgb.size());
      GMC_FUZZ_CHECK(std::isfinite(frame.depth_units) && frame.depth_units > 0);
      GMC_FUZZ_CHECK(std::isfinite(frame.camera.fx) && frame.camera.fx > 0);
      GMC_FUZZ_CHECK(std::isfinite(frame.camera.fy) && frame.camera.fy > 0);
      GMC_FUZZ_CHECK(std::isfinite(frame.camera.cx) && std::isfinite(frame.camera.cy));
      GMC_FUZZ_CHECK(std::isfinite(frame.stamp));
    }
  } catch (const ds::InputError&) {
  }
  return 0;
}
