#pragma once
#include "gmc/apps/app.h"

namespace gmc::apps {

/// gmc-tum2rawlog <tum_dir> <out.rawlog> [--camera PRESET|fx,fy,cx,cy] [--externalize]
/// Ground truth, when present, is copied next to the rawlog as "<name>_groundtruth.txt"
/// (TUM format), interpolated at the RGB stamps.
class Tum2RawlogApp : public App {
 public:
  void initialize(const std::vector<std::string>& args) override;
  int run() override;

 private:
  std::string input_, output_, camera_ = "fr3";
  bool externalize_ = false;
};

}  // namespace gmc::apps
