#pragma once
#include "gmc/apps/app.h"

namespace gmc::apps {

/// gmc-sim <config.ini> --out DIR [--seed N] [--frames N] [--preview I]
/// Writes a TUM-layout folder (rgb/, depth/, rgb.txt, depth.txt, groundtruth.txt),
/// masks/<stamp>.png, sequence.rawlog and scene.xyz (see doc/sim.md); with --preview,
/// preview.png shows frame I's RGB, depth and mask side by side. The folder is
/// assembled under a temporary name and renamed when complete.
class SimApp : public App {
 public:
  void initialize(const std::vector<std::string>& args) override;
  int run() override;

 private:
  std::string config_, out_;
  int seed_ = -1, frames_ = -1, preview_ = -1;
};

}  // namespace gmc::apps
