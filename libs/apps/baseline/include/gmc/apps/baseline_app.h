#pragma once
#include "gmc/apps/app.h"

namespace gmc::apps {

/// gmc-baseline-odometry <input> --out TRAJ.txt [--camera PRESET|fx,fy,cx,cy]
///                       [--method rgbd|icp|rgbd_icp] [--json J.json]
/// Runs OpenCV's rgbd-contrib odometry (frame to frame) on the same frames as
/// gmc-rgbd-mapping, for side-by-side comparisons; prints its median ms per frame
/// (--json: method, frames, failed, unreadable_skipped, ms_median).
class BaselineApp : public App {
 public:
  void initialize(const std::vector<std::string>& args) override;
  int run() override;

 private:
  std::string input_, out_, camera_ = "fr3", method_ = "rgbd", json_;
};

}  // namespace gmc::apps
