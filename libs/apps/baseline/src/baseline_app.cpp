#include "gmc/apps/baseline_app.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "gmc/apps/command_line.h"
#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/camera.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "gmc/vo/opencv_baseline.h"

namespace gmc::apps {
namespace {
const char* kUsage =
    "usage: gmc-baseline-odometry <input.rawlog|tum_dir> --out TRAJ.txt "
    "[--camera fr1|fr2|fr3|bonn|fx,fy,cx,cy] [--method rgbd|icp|rgbd_icp] [--json J.json]";
}

void BaselineApp::initialize(const std::vector<std::string>& args) {
  TCLAP::CmdLine cmd("OpenCV's RGB-D odometry on the same frames", ' ', "", false);
  TCLAP::UnlabeledValueArg<std::string> input("input", "rawlog or TUM folder", true, "", "input.rawlog|tum_dir", cmd);
  TCLAP::ValueArg<std::string> out("", "out", "trajectory to write (TUM format)", true, "", "TRAJ.txt", cmd);
  CameraArg camera(cmd, camera_);
  TCLAP::ValueArg<std::string> method("", "method", "OpenCV odometry", false, method_, "rgbd|icp|rgbd_icp", cmd);
  TCLAP::ValueArg<std::string> json("", "json", "frames, failures and median ms as JSON", false, "", "J.json", cmd);
  parseCommandLine(cmd, "gmc-baseline-odometry", args, kUsage);
  input_ = input.getValue();
  out_ = out.getValue();
  camera_ = camera.getValue();
  method_ = method.getValue();
  json_ = json.getValue();
}

int BaselineApp::run() {
  PinholeCamera camera;
  try {
    camera = datasets::cameraPreset(camera_);
  } catch (const std::invalid_argument& e) {
    throw AppError(std::string("--camera: ") + e.what(), 2);
  }
  std::unique_ptr<vo::OpenCvOdometry> odometry;
  try {
    odometry = std::make_unique<vo::OpenCvOdometry>(method_, camera);
  } catch (const std::invalid_argument& e) {
    throw AppError(std::string("--method: ") + e.what(), 2);
  }
  auto source = datasets::openRgbdSource(input_, camera);
  std::vector<datasets::StampedPose> trajectory;
  std::vector<double> ms;
  size_t failed = 0, skipped = 0;
  datasets::RgbdFrame frame;
  while (true) {
    // One unreadable frame of a good sequence is skipped (and counted); the odometry then
    // matches across the gap, as it would over a dropped frame.
    try {
      if (!source->next(frame)) break;
    } catch (const datasets::FrameReadError& e) {
      std::cerr << "gmc-baseline-odometry: warning: skipping " << e.what() << "\n";
      ++skipped;
      continue;
    }
    cv::Mat gray;
    cv::cvtColor(frame.rgb, gray, cv::COLOR_BGR2GRAY);
    const auto t0 = std::chrono::steady_clock::now();
    bool ok = true;
    const Isometry T = odometry->process(gray, frame.depth, frame.depth_units, ok);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    failed += !ok;
    trajectory.push_back({frame.stamp, T});
  }
  if (trajectory.empty()) throw AppError(input_ + ": no frames");
  datasets::writeTumTrajectory(out_, trajectory);
  std::sort(ms.begin(), ms.end());
  std::printf("OpenCV %s odometry: %zu frames, %zu failed, %zu unreadable skipped, %.2f ms median per frame\n",
              method_.c_str(), trajectory.size(), failed, skipped, ms[ms.size() / 2]);
  if (!json_.empty()) {
    const nlohmann::ordered_json j = {{"method", method_},     {"frames", trajectory.size()},
                                      {"failed", failed},      {"unreadable_skipped", skipped},
                                      {"ms_median", ms[ms.size() / 2]}};
    datasets::writeTextAtomic(json_, j.dump(2) + "\n");
  }
  return 0;
}

}  // namespace gmc::apps
