// Per-frame statistics of the odometry's matches on one RGB-D sequence, computed the same
// way on real recordings and on simulated ones, so the simulator can be calibrated
// against real data (doc/sim.md, scripts/calibrate_sim.sh).
//
//   calibration_stats <config.ini> <tum_dir|file.rawlog> [--camera P] [--set S.k=v ...] [--json FILE]
//
// --camera: intrinsics of a TUM folder, fr1 | fr2 | fr3 (default) | bonn | "fx,fy,cx,cy".
// Runs gmc::vo::RgbdOdometry with the config's [Frontend] [GMS] [GMC] [Odometry]
// [Refinement] sections over every frame and prints p10/p50/p90 over frames (the first
// frame, which has nothing to match, is left out) of: matches, static and dynamic matches,
// the share of matches GMC labels dynamic, the share of matched keypoints in the lower
// half of the image, frames with fewer than 50 static matches; and, where the folder has
// gmc-sim's masks/, the share of pixels on people and of matches on people. Where the
// folder has groundtruth.txt: how far the camera moves and turns per frame
// (camera_step_mm, camera_rotation_deg), next to how far the estimate moves between two
// tracked frames (tracked_step_mm): on a hovering camera the second is mostly noise.
#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gmc/config/ini.h"
#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/camera.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "tool_main.h"
#include "gmc/vo/odometry.h"

namespace {
namespace fs = std::filesystem;
using gmc::MotionLabel;

constexpr int kFewStatic = 50;  ///< "too few static matches" (the issue's threshold)

struct Args {
  std::string config, input, camera = "fr3", json;
  std::vector<std::string> overrides;
};

const char* kUsage =
    "usage: calibration_stats <config.ini> <tum_dir|file.rawlog> [--camera P] [--set S.k=v ...] [--json FILE]";

Args parseArgs(int argc, char** argv) {
  Args a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if ((s == "--camera" || s == "--set" || s == "--json") && i + 1 < argc) {
      const std::string v = argv[++i];
      if (s == "--camera") a.camera = v;
      else if (s == "--set") a.overrides.push_back(v);
      else a.json = v;
    } else if (!s.empty() && s[0] == '-') {
      throw std::invalid_argument("unknown or incomplete option '" + s + "'\n" + kUsage);
    } else {
      positional.push_back(s);
    }
  }
  if (positional.size() != 2) throw std::invalid_argument(kUsage);
  a.config = positional[0], a.input = positional[1];
  return a;
}

gmc::vo::OdometryConfig loadOdometryConfig(const mrpt::config::CConfigFileBase& ini, const std::string& source) {
  gmc::vo::OdometryConfig c;
  gmc::cfg::loadSection(ini, "Frontend", c.frontend, source);
  gmc::cfg::loadSection(ini, "GMS", c.gms, source);
  gmc::cfg::loadSection(ini, "GMC", c.gmc, source);
  gmc::cfg::loadSection(ini, "Odometry", c.odometry, source);
  gmc::cfg::loadSection(ini, "Refinement", c.refinement, source);
  return c;
}

/// Linear interpolation between order statistics (numpy's default percentile).
double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const double pos = p / 100.0 * static_cast<double>(v.size() - 1);
  const size_t lo = static_cast<size_t>(pos), hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

/// The gmc-sim ground-truth mask of a frame read from a TUM folder, if there is one.
cv::Mat maskOf(const std::string& input, const gmc::datasets::RgbdFrame& frame) {
  const fs::path mask = fs::path(input) / "masks" / fs::path(frame.name).filename();
  if (!fs::is_directory(input) || !fs::exists(mask)) return {};
  return cv::imread(mask.string(), cv::IMREAD_GRAYSCALE);
}

using Series = std::map<std::string, std::vector<double>>;

/// One frame's statistics into `series`.
void record(const gmc::vo::FrameTracking& t, const cv::Mat& mask, int height, Series& series) {
  int matched = 0, lower = 0, on_people = 0;
  for (size_t k = 0; k < t.keypoints.size(); ++k) {
    if (t.keypoint_labels[k] == MotionLabel::Undecided) continue;
    ++matched;
    const cv::Point2f& p = t.keypoints[k];
    if (p.y >= 0.5 * height) ++lower;
    if (!mask.empty() && mask.at<std::uint8_t>(cvRound(p.y), cvRound(p.x))) ++on_people;
  }
  series["matches"].push_back(t.num_matches);
  series["static"].push_back(t.num_static);
  series["dynamic"].push_back(t.num_dynamic);
  // Of the keypoints labelled static or dynamic: the odometry also labels keypoints it
  // matched only to the previous frame, so num_dynamic can exceed the map matches.
  series["dynamic_share"].push_back(t.num_dynamic / std::max(1.0, static_cast<double>(t.num_static + t.num_dynamic)));
  series["lower_half_share"].push_back(matched > 0 ? static_cast<double>(lower) / matched : 0.0);
  if (mask.empty()) return;
  series["people_pixels"].push_back(cv::countNonZero(mask) / static_cast<double>(mask.total()));
  series["matches_on_people"].push_back(matched > 0 ? static_cast<double>(on_people) / matched : 0.0);
}

/// The ground truth of a TUM folder (empty when it has none): positions and rotation
/// angles only, which a rigid change of body frame (Bonn's marker) barely moves.
std::vector<gmc::datasets::StampedPose> groundTruthOf(const std::string& input) {
  const fs::path gt = fs::path(input) / "groundtruth.txt";
  if (!fs::is_directory(input) || !fs::exists(gt)) return {};
  return gmc::datasets::readTumTrajectory(gt.string());
}

/// The camera's and the estimate's motion from the previous frame to this one.
struct MotionRecorder {
  std::vector<gmc::datasets::StampedPose> truth;
  std::optional<gmc::Isometry> previous_truth = std::nullopt, previous_estimate = std::nullopt;

  void record(double stamp, const gmc::vo::FrameTracking& t, Series& series) {
    const auto now = truth.empty() ? std::nullopt : gmc::datasets::interpolatePose(truth, stamp);
    if (now && previous_truth) {
      const gmc::Isometry step = previous_truth->inverse() * *now;
      series["camera_step_mm"].push_back(1e3 * step.translation().norm());
      series["camera_rotation_deg"].push_back(Eigen::AngleAxisd(step.linear()).angle() * 180.0 / M_PI);
    }
    previous_truth = now;
    const bool tracked = t.state == gmc::vo::TrackingState::Tracking;
    if (tracked && previous_estimate)
      series["tracked_step_mm"].push_back(
          1e3 * (t.T_world_camera.translation() - previous_estimate->translation()).norm());
    previous_estimate = tracked ? std::optional<gmc::Isometry>(t.T_world_camera) : std::nullopt;
  }
};

std::string report(const Args& args, const Series& series, int frames) {
  std::string json = "{\n  \"input\": \"" + args.input + "\",\n  \"frames\": " + std::to_string(frames) + ",\n";
  const auto& stat = series.at("static");
  const auto few = std::count_if(stat.begin(), stat.end(), [](double s) { return s < kFewStatic; });
  json += "  \"frames_static_below_50\": " + std::to_string(few) + ",\n";
  std::printf("%-20s %10s %10s %10s\n", "per frame", "p10", "p50", "p90");
  char line[256];
  size_t k = 0;
  for (const auto& [name, values] : series) {
    const double p10 = percentile(values, 10), p50 = percentile(values, 50), p90 = percentile(values, 90);
    std::printf("%-20s %10.3f %10.3f %10.3f\n", name.c_str(), p10, p50, p90);
    std::snprintf(line, sizeof line, "  \"%s\": {\"p10\": %.4f, \"p50\": %.4f, \"p90\": %.4f}%s\n", name.c_str(), p10,
                  p50, p90, ++k < series.size() ? "," : "");
    json += line;
  }
  std::printf("frames with < %d static matches: %ld of %zu\n", kFewStatic, static_cast<long>(few), stat.size());
  return json + "}\n";
}

int run(const Args& args) {
  auto ini = gmc::cfg::loadIniFile(args.config);
  gmc::cfg::applyOverrides(ini, args.overrides);
  gmc::vo::RgbdOdometry odometry(loadOdometryConfig(ini, args.config));
  auto source = gmc::datasets::openRgbdSource(args.input, gmc::datasets::cameraPreset(args.camera));
  Series series;
  gmc::datasets::RgbdFrame frame;
  cv::Mat gray;
  MotionRecorder motion{groundTruthOf(args.input)};
  int frames = 0;
  while (source->next(frame)) {
    cv::cvtColor(frame.rgb, gray, cv::COLOR_BGR2GRAY);
    const auto t = odometry.process(gray, frame.depth, frame.depth_units, frame.camera, frame.stamp);
    if (frames++ > 0) record(t, maskOf(args.input, frame), frame.rgb.rows, series);
    motion.record(frame.stamp, t, series);
  }
  if (series.empty()) throw std::runtime_error(args.input + ": fewer than two frames");
  const std::string json = report(args, series, frames);
  if (!args.json.empty()) gmc::datasets::writeTextAtomic(args.json, json);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return toolMain("calibration_stats", argc, argv, parseArgs, run); }
