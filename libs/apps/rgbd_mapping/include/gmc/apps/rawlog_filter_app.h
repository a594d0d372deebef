#pragma once
#include "gmc/apps/app.h"

namespace gmc::apps {

/// gmc-rawlog-filter <config.ini> <input.rawlog|tum_dir> <out.rawlog> [--set S.k=v ...]
/// Applies the INI filter chain ([Filters] chain = ...) to every observation and writes
/// the kept ones (with GMC's "dynamic" pixel labels) to a new rawlog that MRPT's
/// rawlog-edit and RawLogViewer open.
class RawlogFilterApp : public App {
 public:
  void initialize(const std::vector<std::string>& args) override;
  int run() override;

 private:
  std::string config_, input_, output_;
  std::vector<std::string> overrides_;
};

}  // namespace gmc::apps
