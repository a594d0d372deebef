#include "gmc/apps/rawlog_filter_app.h"

#include <cstdio>
#include <iostream>

#include "gmc/apps/rgbd_mapping_app.h"
#include "gmc/config/ini.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/source.h"
#include "gmc/filters/filter.h"

namespace gmc::apps {
namespace {
const char* kUsage =
    "usage: gmc-rawlog-filter <config.ini> <input.rawlog|tum_dir> <out.rawlog> [--set Section.key=value ...]";
}

void RawlogFilterApp::initialize(const std::vector<std::string>& args) {
  std::vector<std::string> positional;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--set") {
      if (i + 1 >= args.size()) throw AppError("--set needs a value\n" + std::string(kUsage), 2);
      overrides_.push_back(args[++i]);
    } else if (!args[i].empty() && args[i][0] == '-') {
      throw AppError("unknown option '" + args[i] + "'\n" + kUsage, 2);
    } else {
      positional.push_back(args[i]);
    }
  }
  if (positional.size() != 3) throw AppError(kUsage, 2);
  config_ = positional[0], input_ = positional[1], output_ = positional[2];
}

int RawlogFilterApp::run() {
  auto ini = cfg::loadIniFile(config_);
  cfg::applyOverrides(ini, overrides_);
  const PipelineConfig config = loadPipelineConfig(ini, config_);
  filters::FilterChain chain = filters::buildChain(ini, config_);
  auto source = datasets::openRgbdSource(input_, config.camera);
  datasets::RawlogWriter writer(output_);
  size_t read = 0, skipped = 0;
  datasets::RgbdFrame frame;
  while (true) {
    try {
      if (!source->next(frame)) break;
    } catch (const datasets::FrameReadError& e) {
      std::cerr << "gmc-rawlog-filter: warning: skipping " << e.what() << "\n";
      ++skipped;
      continue;
    }
    auto obs = datasets::toObservation(frame);
    filters::FilterContext ctx;
    ctx.frame_index = read++;
    if (filters::applyChain(chain, *obs, ctx)) writer.write(*obs);
  }
  writer.close();
  std::printf("%s: %zu of %zu observations kept (%zu unreadable skipped)\n", output_.c_str(),
              writer.count(), read, skipped);
  return 0;
}

}  // namespace gmc::apps
