#include "gmc/apps/rawlog_filter_app.h"

#include <cstdio>
#include <iostream>
#include <map>

#include "gmc/apps/command_line.h"
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
  CommandLine line("gmc-rawlog-filter", kUsage);
  TCLAP::MultiArg<std::string> set("", "set", "override one INI key", false, "Section.key=value", line.cmd());
  TCLAP::UnlabeledMultiArg<std::string> positional("files", "config, input, output", false, "path", line.cmd());
  line.parse(args);
  if (positional.getValue().size() != 3) line.fail("expected <config.ini> <input> <out.rawlog>");
  overrides_ = set.getValue();
  config_ = positional.getValue()[0], input_ = positional.getValue()[1], output_ = positional.getValue()[2];
}

int RawlogFilterApp::run() {
  auto ini = cfg::loadIniFile(config_);
  cfg::applyOverrides(ini, overrides_);
  const PipelineConfig config = loadPipelineConfig(ini, config_);
  // One chain per camera (a gmc filter tracks one camera); the first is built and checked
  // before the output is opened.
  std::map<std::string, filters::FilterChain> chains;
  filters::FilterChain first_chain = filters::buildChain(ini, config_);
  datasets::SensorSelection sensors = config.sensors;
  sensors.single_camera = false;  // every selected camera is filtered
  auto source = datasets::openRgbdSource(input_, config.camera, sensors, config.distortion, config.label_masks);
  datasets::RawlogWriter writer(output_);
  source->setObjectSink(&writer);  // every object passes on, in order
  size_t read = 0, skipped = 0, dropped = 0;
  datasets::RgbdFrame frame;
  while (true) {
    try {
      if (!source->next(frame)) break;
    } catch (const datasets::FrameReadError& e) {
      // Not filtered; a rawlog's object still passes on as it was read.
      std::cerr << "gmc-rawlog-filter: warning: skipping " << e.what() << "\n";
      ++skipped;
      continue;
    }
    auto [chain, created] = chains.try_emplace(frame.sensor_label);
    if (created) chain->second = chains.size() == 1 ? std::move(first_chain) : filters::buildChain(ini, config_);
    auto obs = datasets::observationOf(frame);
    filters::FilterContext ctx;
    ctx.frame_index = read++;
    if (filters::applyChain(chain->second, *obs, ctx)) {
      writer.write(*obs);
    } else {
      writer.drop(*obs);
      ++dropped;
    }
  }
  for (auto& camera_chain : chains) {  // the input has ended for every camera's chain
    filters::FilterContext end;
    filters::finishChain(camera_chain.second, end);
  }
  writer.close();
  std::printf("%s: %zu objects written; %zu RGB-D observations filtered, %zu dropped by the "
              "chain, %zu unreadable not filtered\n",
              output_.c_str(), writer.count(), read, dropped, skipped);
  return 0;
}

}  // namespace gmc::apps
