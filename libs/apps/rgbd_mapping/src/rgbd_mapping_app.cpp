#include "gmc/apps/rgbd_mapping_app.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "gmc/apps/command_line.h"
#include "gmc/apps/config_files.h"
#include "gmc/apps/pipeline_report.h"
#include "gmc/config/ini.h"
#include "gmc/datasets/atomic_file.h"
#include "gmc/datasets/camera.h"
#include "gmc/datasets/rawlog.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/tum.h"
#include "gmc/filters/filter.h"
#include "gmc/filters/gmc_filter.h"
#include "gmc/mapping/map_quality.h"
#include "gmc/mapping/static_map.h"

namespace gmc::apps {

std::atomic<bool> RgbdMappingApp::stop_requested_{false};

void RgbdMappingApp::requestStop() { stop_requested_ = true; }

namespace {

struct MemorySample {
  double frame, resident_mb, map_nodes, heap_mb;
};

/// memory.png: resident memory (MB, red, left scale) and map nodes (blue, right scale)
/// against the frame number, both from zero.
cv::Mat plotMemory(const std::vector<MemorySample>& samples) {
  const int W = 800, H = 400, left = 70, right = 80, top = 40, bottom = 50;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double max_f = 1, max_mb = 1, max_nodes = 1;
  for (const auto& s : samples) {
    max_f = std::max(max_f, s.frame);
    max_mb = std::max(max_mb, s.resident_mb * 1.1);
    max_nodes = std::max(max_nodes, s.map_nodes * 1.1);
  }
  auto px = [&](double f, double v, double vmax) {
    return cv::Point(left + static_cast<int>((W - left - right) * f / max_f),
                     H - bottom - static_cast<int>((H - top - bottom) * v / vmax));
  };
  cv::rectangle(img, {left, top}, {W - right, H - bottom}, cv::Scalar(0, 0, 0));
  for (size_t i = 1; i < samples.size(); ++i) {
    const auto& a = samples[i - 1];
    const auto& b = samples[i];
    cv::line(img, px(a.frame, a.resident_mb, max_mb), px(b.frame, b.resident_mb, max_mb), {0, 0, 220}, 2);
    cv::line(img, px(a.frame, a.map_nodes, max_nodes), px(b.frame, b.map_nodes, max_nodes), {200, 0, 0}, 2);
    cv::line(img, px(a.frame, a.heap_mb, max_mb), px(b.frame, b.heap_mb, max_mb), {0, 150, 255}, 2);
  }
  auto text = [&](const std::string& t, cv::Point p, cv::Scalar c) {
    cv::putText(img, t, p, cv::FONT_HERSHEY_SIMPLEX, 0.45, c, 1, cv::LINE_AA);
  };
  char buf[96];
  std::snprintf(buf, sizeof buf, "resident memory (MB), max %.0f", max_mb / 1.1);
  text(buf, {left, 25}, {0, 0, 220});
  text("orange: heap in use (MB)", {left + 260, 25}, {0, 150, 255});
  std::snprintf(buf, sizeof buf, "map nodes, max %.0f", max_nodes / 1.1);
  text(buf, {W - right - 200, 25}, {200, 0, 0});
  text("0", {left - 15, H - bottom + 5}, {0, 0, 0});
  std::snprintf(buf, sizeof buf, "%.0f", max_mb);
  text(buf, {5, top + 5}, {0, 0, 220});
  std::snprintf(buf, sizeof buf, "%.0f", max_nodes);
  text(buf, {W - right + 5, top + 5}, {200, 0, 0});
  std::snprintf(buf, sizeof buf, "frame %.0f", max_f);
  text(buf, {W - right - 70, H - bottom + 20}, {0, 0, 0});
  text("frame 0", {left, H - bottom + 20}, {0, 0, 0});
  return img;
}

const char* kUsage =
    "usage: gmc-rgbd-mapping [<config.ini>] <input.rawlog|tum_dir> --out DIR "
    "[--config NAME|FILE] [--set Section.key=value ...] [--print-config]";

void onSignal(int) { RgbdMappingApp::requestStop(); }

/// Draws keypoints coloured by label and the dynamic GMC cells over the image.
/// `truth_mask` (simulated input, may be empty): outlined in cyan, so what the dynamic
/// mask misses is visible.
cv::Mat drawOverlay(const datasets::RgbdFrame& frame, const vo::FrameTracking& t,
                    const cv::Mat& mask, const cv::Mat& truth_mask) {
  // Grey, dimmed background so the coloured labels stand out on any texture.
  cv::Mat img;
  if (frame.rgb.channels() == 3) cv::cvtColor(frame.rgb, img, cv::COLOR_BGR2GRAY);
  else img = frame.rgb.clone();
  img.convertTo(img, CV_8U, 0.6, 40);
  cv::cvtColor(img, img, cv::COLOR_GRAY2BGR);
  if (!mask.empty()) {
    cv::Mat red(img.size(), CV_8UC3, cv::Scalar(0, 0, 255));
    cv::Mat blended;
    cv::addWeighted(img, 0.6, red, 0.4, 0, blended);
    blended.copyTo(img, mask);
  }
  if (!truth_mask.empty()) {
    std::vector<std::vector<cv::Point>> outlines;
    cv::findContours(truth_mask > 0, outlines, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    cv::drawContours(img, outlines, -1, cv::Scalar(255, 255, 0), 2);
  }
  for (const auto& cell : t.gmc.cells) {
    if (cell.cluster < 0 || t.gmc.clusters[static_cast<size_t>(cell.cluster)].is_static) continue;
    cv::rectangle(img, cv::Rect(cell.x0, cell.y0, cell.x1 - cell.x0, cell.y1 - cell.y0),
                  cv::Scalar(0, 200, 255), 1);
  }
  for (size_t i = 0; i < t.keypoints.size(); ++i) {
    const auto label = t.keypoint_labels[i];
    const cv::Scalar colour = label == MotionLabel::Static    ? cv::Scalar(0, 220, 0)
                              : label == MotionLabel::Dynamic ? cv::Scalar(0, 0, 255)
                                                              : cv::Scalar(160, 160, 160);
    if (label != MotionLabel::Undecided) cv::circle(img, t.keypoints[i], 5, cv::Scalar(0, 0, 0), cv::FILLED);
    cv::circle(img, t.keypoints[i], label == MotionLabel::Undecided ? 2 : 4, colour,
               label == MotionLabel::Undecided ? 1 : cv::FILLED);
  }
  std::ostringstream text;
  text << std::fixed << std::setprecision(6) << frame.stamp << "  " << vo::toString(t.state)
       << "  static " << t.num_static << "  dynamic " << t.num_dynamic;
  cv::putText(img, text.str(), {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 2);
  cv::putText(img, text.str(), {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1);
  return img;
}

/// Ground-truth mask of a simulated frame: masks/<stamp with 6 decimals>.png.
cv::Mat loadMask(const std::string& dir, double stamp) {
  char name[48];
  std::snprintf(name, sizeof name, "/%.6f.png", stamp);
  return cv::imread(dir + name, cv::IMREAD_GRAYSCALE);
}

gmc::PinholeCamera cameraFromOptions(const DatasetOptions& o) {
  if (o.camera == "custom") {
    gmc::PinholeCamera c;
    c.fx = o.fx;
    c.fy = o.fy;
    c.cx = o.cx;
    c.cy = o.cy;
    return c;
  }
  return datasets::cameraPreset(o.camera);
}

}  // namespace

PipelineConfig loadPipelineConfig(const mrpt::config::CConfigFileBase& ini, const std::string& source) {
  PipelineConfig c;
  cfg::loadSection(ini, "Dataset", c.dataset, source);
  cfg::loadSection(ini, "Playback", c.playback, source);
  cfg::loadSection(ini, "Output", c.output, source);
  cfg::loadSection(ini, "Mapping", c.map, source);
  std::set<std::string> known = {"Dataset", "Playback", "Output", "Mapping"};
  for (const auto& section : filters::filterSections(ini, source)) known.insert(section);
  const auto unknown = cfg::unknownSections(ini, known);
  if (!unknown.empty()) throw cfg::ConfigError(source + ": unknown section [" + unknown.front() + "]");
  c.camera = cameraFromOptions(c.dataset);
  c.sensors.labels = datasets::splitList(filters::loadChainOptions(ini, source).sensor_label);
  c.sensors.single_camera = true;
  if (c.dataset.undistort == "auto") c.distortion = datasets::presetDistortion(c.dataset.camera);
  return c;
}

void RgbdMappingApp::scoreAgainstMask(const datasets::RgbdFrame& frame, const cv::Mat& mask,
                                      const vo::FrameTracking& tracking, const cv::Mat& dynamic_mask,
                                      double max_range, PipelineReport& report) const {
  if (mask.empty()) throw AppError(masks_dir_ + ": no mask for frame " + frame.name);
  for (size_t i = 0; i < tracking.keypoints.size(); ++i) {
    const auto& kp = tracking.keypoints[i];
    const bool on_person = mask.at<std::uint8_t>(static_cast<int>(kp.y + 0.5f), static_cast<int>(kp.x + 0.5f)) > 0;
    const auto label = tracking.keypoint_labels[i];
    if (label == MotionLabel::Undecided) continue;  // unmatched, or no decision
    report.mask_score.add(label == MotionLabel::Dynamic, on_person);
  }
  // Pixels the map could insert: depth within its range.
  const auto max_raw = static_cast<std::uint16_t>(std::min(65535.0, max_range / frame.depth_units));
  for (int v = 0; v < frame.depth.rows; ++v) {
    const auto* depth_row = frame.depth.ptr<std::uint16_t>(v);
    const auto* truth_row = mask.ptr<std::uint8_t>(v);
    const auto* predicted_row = dynamic_mask.empty() ? nullptr : dynamic_mask.ptr<std::uint8_t>(v);
    for (int u = 0; u < frame.depth.cols; ++u) {
      if (depth_row[u] == 0 || depth_row[u] > max_raw) continue;
      report.pixel_mask_score.add(predicted_row && predicted_row[u] > 0, truth_row[u] > 0);
    }
  }
}

void RgbdMappingApp::initialize(const std::vector<std::string>& args) {
  CommandLine line("gmc-rgbd-mapping", kUsage);
  TCLAP::ValueArg<std::string> out("", "out", "output folder", false, "", "DIR", line.cmd());
  TCLAP::MultiArg<std::string> set("", "set", "override one INI key", false, "Section.key=value", line.cmd());
  TCLAP::ValueArg<std::string> config("", "config", "INI file, or the name of a shipped one", false, "", "NAME|FILE", line.cmd());
  TCLAP::SwitchArg print("", "print-config", "print the effective configuration and stop", line.cmd(), false);
  TCLAP::UnlabeledMultiArg<std::string> positional("paths", "[config.ini] input", false, "path", line.cmd());
  line.parse(args);
  const InvocationPaths paths = invocationPaths(positional.getValue(), config.getValue(), print.getValue());
  if (!paths.error.empty()) line.fail(paths.error);
  if (!print.getValue() && out.getValue().empty()) line.fail("--out DIR is required");
  config_path_ = paths.config, input_path_ = paths.input;
  out_dir_ = out.getValue(), overrides_ = set.getValue(), print_config_ = print.getValue();
}

int RgbdMappingApp::run() {
  namespace fs = std::filesystem;
  if (print_config_) return printEffectiveConfig(config_path_, overrides_);
  stop_requested_ = false;
  // --- configuration (strict: every section we own is checked)
  auto ini = cfg::loadIniFile(config_path_);
  cfg::applyOverrides(ini, overrides_);
  const PipelineConfig config = loadPipelineConfig(ini, config_path_);
  const DatasetOptions& dataset = config.dataset;
  const PlaybackOptions& playback = config.playback;
  const OutputOptions& output = config.output;
  const mapping::StaticMapOptions& map_options = config.map;
  filters::FilterChain chain = filters::buildChain(ini, config_path_, {filters::kTracking});
  const gmc::PinholeCamera& camera = config.camera;
  std::unique_ptr<datasets::RgbdSource> source = datasets::openRgbdSource(input_path_, camera, config.sensors, config.distortion);

  // Ground truth, to anchor the first pose (maps comparable with a simulated scene).
  std::string gt_path = dataset.groundtruth;
  if (gt_path == "auto") {
    gt_path = (fs::path(input_path_) / "groundtruth.txt").string();
    if (!fs::is_directory(input_path_) || !fs::exists(gt_path)) gt_path.clear();
  }
  std::vector<datasets::StampedPose> groundtruth;
  if (!gt_path.empty()) groundtruth = datasets::readGroundTruth(gt_path, dataset.groundtruth_frame);
  if (dataset.anchor_to_groundtruth && groundtruth.empty())
    throw AppError(config_path_ + ": [Dataset] anchor_to_groundtruth needs a groundtruth file");

  fs::create_directories(out_dir_);
  std::unique_ptr<mapping::StaticMapBuilder> map;
  if (output.map) map = std::make_unique<mapping::StaticMapBuilder>(map_options);
  // Simulated input anchored to its ground truth: measure ghost voxels and coverage.
  std::unique_ptr<mapping::GroundTruthVoxels> truth_voxels;
  if (map && dataset.anchor_to_groundtruth && fs::is_directory(fs::path(input_path_) / "masks"))
    truth_voxels = std::make_unique<mapping::GroundTruthVoxels>(map_options);
  std::unique_ptr<datasets::RawlogWriter> filtered;
  if (output.filtered_rawlog)
    filtered = std::make_unique<datasets::RawlogWriter>((fs::path(out_dir_) / "filtered.rawlog").string());
  if (filtered) source->setObjectSink(filtered.get());  // the rawlog's other objects pass on
  if (output.overlay_every > 0) fs::create_directories(fs::path(out_dir_) / "overlays");

  auto old_int = std::signal(SIGINT, onSignal);
  auto old_term = std::signal(SIGTERM, onSignal);

  PipelineReport report;
  const bool has_masks = fs::is_directory(fs::path(input_path_) / "masks");
  masks_dir_ = (fs::path(input_path_) / "masks").string();
  report.has_mask_score = has_masks;
  std::vector<datasets::StampedPose> trajectory;
  Isometry T_anchor = Isometry::Identity();
  const bool tty = playback.progress && isatty(fileno(stderr));
  const size_t total_hint = source->sizeHint();
  const auto wall_start = std::chrono::steady_clock::now();
  double first_stamp = -1;
  size_t index = 0;
  datasets::RgbdFrame frame;
  // [Dataset] repeat: later passes reopen the input and shift stamps past the last one.
  int pass = 0;
  double stamp_shift = 0, pass_first_stamp = -1, last_stamp = 0, frame_interval = 1.0 / 30.0;
  std::ostringstream memory_rows;
  std::vector<MemorySample> memory;
  if (output.memory_every > 0) memory_rows << "frame,resident_mb,map_nodes,heap_in_use_mb\n";
  while (!stop_requested_) {
    bool have = false;
    try {
      have = source->next(frame);
    } catch (const datasets::FrameReadError& e) {
      std::cerr << "gmc-rgbd-mapping: warning: skipping " << e.what() << "\n";
      ++report.skipped;
      continue;
    }
    if (!have && pass + 1 < dataset.repeat && pass_first_stamp >= 0) {
      ++pass;
      stamp_shift += last_stamp - pass_first_stamp + frame_interval;
      pass_first_stamp = -1;
      source = datasets::openRgbdSource(input_path_, camera, config.sensors, config.distortion);
      continue;
    }
    if (!have) break;
    if (pass_first_stamp < 0) pass_first_stamp = frame.stamp;
    else frame_interval = std::max(1e-3, frame.stamp - last_stamp);
    last_stamp = frame.stamp;
    const double recorded_stamp = frame.stamp;  // masks and ground truth are looked up by it
    frame.stamp += stamp_shift;
    const bool first_pass = pass == 0;
    const size_t this_index = index++;
    if (static_cast<int>(this_index) < dataset.first_frame) continue;
    if (dataset.max_frames > 0 && report.frames >= static_cast<size_t>(dataset.max_frames)) break;

    // Realtime playback: frames whose time has passed while we were busy are dropped.
    if (playback.mode == "realtime") {
      if (first_stamp < 0) first_stamp = frame.stamp;
      const double due = (frame.stamp - first_stamp) / playback.rate;
      const double now = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      if (now > due + 1.0 / 30.0 && report.frames > 0) {
        ++report.dropped;
        continue;
      }
      if (now < due) std::this_thread::sleep_for(std::chrono::duration<double>(due - now));
    }

    const auto t0 = std::chrono::steady_clock::now();
    auto obs = datasets::observationOf(frame);
    filters::FilterContext ctx;
    ctx.frame_index = this_index;
    if (!filters::applyChain(chain, *obs, ctx)) {  // decimated
      if (filtered) filtered->drop(*obs);
      continue;
    }
    vo::FrameTracking& tracking = *filters::trackingOf(ctx);  // the chain was checked to set it
    if (report.frames == 0 && dataset.anchor_to_groundtruth) {
      const auto gt = datasets::interpolatePose(groundtruth, frame.stamp);
      if (!gt) throw AppError(gt_path + ": no ground-truth pose near the first frame");
      T_anchor = *gt * tracking.T_world_camera.inverse();
    }
    const Isometry T_world_camera = T_anchor * tracking.T_world_camera;
    trajectory.push_back({frame.stamp, T_world_camera});

    double map_ms = 0;
    if (map && tracking.tracked()) {  // the builder skips frames per [Mapping] insert_every_n_frames
      const auto tm = std::chrono::steady_clock::now();
      if (map->insertFrame(frame, ctx.dynamic_mask, T_world_camera))
        map_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - tm).count();
    }
    if (filtered) filtered->write(*obs);
    const bool draw_overlay = output.overlay_every > 0 && report.frames % output.overlay_every == 0;
    // Simulated input: the frame's ground-truth mask, read once for the overlay, the scores
    // and the map metrics (the last two on the first pass only: later passes read none).
    const cv::Mat truth_mask =
        has_masks && (first_pass || draw_overlay) ? loadMask(masks_dir_, recorded_stamp) : cv::Mat();
    if (draw_overlay) {
      std::ostringstream name;
      name << std::fixed << std::setprecision(6) << frame.stamp << ".png";
      datasets::writeImageAtomic((fs::path(out_dir_) / "overlays" / name.str()).string(),
                                 drawOverlay(frame, tracking, ctx.dynamic_mask, truth_mask));
    }
    if (first_pass && has_masks)
      scoreAgainstMask(frame, truth_mask, tracking, ctx.dynamic_mask, map_options.max_range, report);
    if (first_pass && truth_voxels) {
      const auto gt_pose = datasets::interpolatePose(groundtruth, recorded_stamp);
      if (gt_pose) truth_voxels->addFrame(frame, truth_mask, *gt_pose);
    }
    const double pipeline_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    report.addFrame(tracking, map_ms, pipeline_ms);
    if (output.memory_every > 0 && report.frames % static_cast<size_t>(output.memory_every) == 0) {
      const MemorySample m{static_cast<double>(report.frames), residentMemoryMb(),
                           static_cast<double>(map ? map->tree().size() : 0), heapInUseMb()};
      memory.push_back(m);
      memory_rows << report.frames << "," << m.resident_mb << "," << m.map_nodes << "," << m.heap_mb << "\n";
    }
    if (tracking.state == vo::TrackingState::Lost)
      std::cerr << "gmc-rgbd-mapping: frame " << this_index << " (" << frame.name
                << ") lost: " << tracking.lost_reason << "\n";

    if (tty) {
      const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      const double fps = report.frames / std::max(el, 1e-9);
      std::fprintf(stderr, "\rframe %zu", this_index + 1);
      if (total_hint) std::fprintf(stderr, "/%zu", total_hint);
      std::fprintf(stderr, "  %.1f fps", fps);
      if (total_hint && fps > 0)
        std::fprintf(stderr, "  ETA %.0f s", (static_cast<double>(total_hint) - this_index - 1) / fps);
      std::fprintf(stderr, "  %s   ", vo::toString(tracking.state));
    }
  }
  if (tty) std::fprintf(stderr, "\n");
  std::signal(SIGINT, old_int);
  std::signal(SIGTERM, old_term);
  report.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  report.interrupted = stop_requested_;
  report.peak_rss_mb = peakResidentMemoryMb();
  if (output.memory_every > 0) {
    datasets::writeTextAtomic((fs::path(out_dir_) / "memory.csv").string(), memory_rows.str());
    datasets::writeImageAtomic((fs::path(out_dir_) / "memory.png").string(), plotMemory(memory));
  }

  // --- outputs, each written to a temporary name and renamed when complete
  datasets::writeTumTrajectory((fs::path(out_dir_) / "trajectory_tum.txt").string(), trajectory);
  datasets::writeBaseTrajectory((fs::path(out_dir_) / "trajectory_base_tum.txt").string(), trajectory, source->baseCamera());
  if (map) {
    map->writeBinary((fs::path(out_dir_) / "map.bt").string());
    report.map = map->stats();
    report.has_map = true;
    if (truth_voxels) {
      report.map_quality = truth_voxels->evaluate(map->tree());
      report.has_map_quality = true;
    }
  }
  if (filtered) filtered->close();
  datasets::writeTextAtomic((fs::path(out_dir_) / "summary.json").string(), report.toJson());
  std::cout << report.toText();
  if (report.frames == 0) throw AppError(input_path_ + ": no frame could be processed");
  return 0;
}

}  // namespace gmc::apps
