#include "gmc/apps/tum2rawlog_app.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "gmc/apps/command_line.h"
#include "gmc/datasets/camera.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"

namespace gmc::apps {
namespace fs = std::filesystem;
namespace {
const char* kUsage =
    "usage: gmc-tum2rawlog <tum_dir> <out.rawlog> [--camera fr1|fr2|fr3|bonn|fx,fy,cx,cy] "
    "[--externalize]";
}

void Tum2RawlogApp::initialize(const std::vector<std::string>& args) {
  TCLAP::CmdLine cmd("TUM/Bonn folder to MRPT rawlog", ' ', "", false);
  TCLAP::UnlabeledValueArg<std::string> input("tum_dir", "TUM-layout folder", true, "", "tum_dir", cmd);
  TCLAP::UnlabeledValueArg<std::string> output("out", "rawlog to write", true, "", "out.rawlog", cmd);
  CameraArg camera(cmd, camera_);
  TCLAP::SwitchArg externalize("", "externalize", "images in <name>_Images/ next to the rawlog", cmd);
  parseCommandLine(cmd, "gmc-tum2rawlog", args, kUsage);
  input_ = input.getValue();
  output_ = output.getValue();
  camera_ = camera.getValue();
  externalize_ = externalize.getValue();
}

int Tum2RawlogApp::run() {
  if (!fs::is_directory(input_)) throw AppError(input_ + ": not a TUM-layout folder");
  PinholeCamera camera;
  try {
    camera = datasets::cameraPreset(camera_);
  } catch (const std::invalid_argument& e) {
    throw AppError(std::string("--camera: ") + e.what(), 2);
  }
  const auto start = std::chrono::steady_clock::now();
  // Unpaired RGB frames are skipped, each named (the source pairs the same way).
  const std::string rgb_list = (fs::path(input_) / "rgb.txt").string();
  const auto unpaired = datasets::pairTumFolder(input_).unpaired_rgb;
  for (const auto& e : unpaired)
    std::fprintf(stderr, "gmc-tum2rawlog: warning: %s:%zu: %s has no depth frame within 0.02 s (skipped)\n",
                 rgb_list.c_str(), e.line, e.path.c_str());
  auto source = datasets::openRgbdSource(input_, camera);
  datasets::RawlogWriter writer(output_, externalize_);
  std::vector<double> stamps;
  datasets::RgbdFrame frame;
  while (source->next(frame)) {  // a bad frame is an error here: a converter must not drop data
    writer.write(frame);
    stamps.push_back(frame.stamp);
  }
  const fs::path gt_path = fs::path(input_) / "groundtruth.txt";
  std::string gt_out;
  size_t gt_poses = 0;
  if (fs::exists(gt_path)) {
    // Bonn's file holds the marker body: the sibling file is the camera, as evaluators expect.
    const auto gt = datasets::readGroundTruth(gt_path.string(), camera_ == "bonn" ? "bonn" : "camera");
    std::vector<datasets::StampedPose> at_frames;
    for (double s : stamps)
      if (auto T = datasets::interpolatePose(gt, s)) at_frames.push_back({s, *T});
    const fs::path out(output_);
    gt_out = (out.parent_path() / (out.stem().string() + "_groundtruth.txt")).string();
    datasets::writeTumTrajectory(gt_out, at_frames);
    gt_poses = at_frames.size();
  }
  writer.close();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s: %zu observations, %zu RGB frames without depth skipped (%.2f s, %.1f frames/s)\n",
              output_.c_str(), writer.count(), unpaired.size(), seconds,
              writer.count() / std::max(seconds, 1e-9));
  if (!gt_out.empty())
    std::printf("%s: ground truth at %zu of %zu frame stamps%s\n", gt_out.c_str(), gt_poses,
                stamps.size(), camera_ == "bonn" ? " (Bonn marker body converted to the camera)" : "");
  return 0;
}

}  // namespace gmc::apps
