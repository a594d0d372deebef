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
#include "gmc/apps/mapping_observers.h"
#include "gmc/apps/mapping_pipeline.h"
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

const char* kUsage =
    "usage: gmc-rgbd-mapping [<config.ini>] <input.rawlog|tum_dir> --out DIR "
    "[--config NAME|FILE] [--set Section.key=value ...] [--print-config]";

void onSignal(int) { RgbdMappingApp::requestStop(); }

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
  c.label_masks = {c.dataset.label_masks, c.dataset.label_masks_name};
  return c;
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

namespace {

/// Installs the stop handlers for SIGINT and SIGTERM; puts the previous ones back when it
/// goes out of scope, also when run() throws.
class SignalGuard {
 public:
  SignalGuard() : old_int_(std::signal(SIGINT, onSignal)), old_term_(std::signal(SIGTERM, onSignal)) {}
  ~SignalGuard() {
    std::signal(SIGINT, old_int_);
    std::signal(SIGTERM, old_term_);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  using Handler = void (*)(int);
  Handler old_int_, old_term_;
};

/// [Dataset] groundtruth, "auto" resolved against the input folder (empty when none).
std::string groundTruthPath(const DatasetOptions& dataset, const std::string& input) {
  namespace fs = std::filesystem;
  if (dataset.groundtruth != "auto") return dataset.groundtruth;
  const std::string path = (fs::path(input) / "groundtruth.txt").string();
  return fs::is_directory(input) && fs::exists(path) ? path : std::string();
}

/// One run: the reader thread, the odometry on the calling thread, the map thread, and
/// the observers; members are declared so that the threads end before what they use.
class MappingRun {
 public:
  MappingRun(const PipelineConfig& config, filters::FilterChain chain, const std::string& input,
             const std::string& out_dir, const std::string& config_path, const std::atomic<bool>& stop);
  /// Plays the input to its end (or a stop request); the stages are finished on return.
  void play();
  /// trajectory, map, summary (each written to a temporary name, then renamed).
  const PipelineReport& writeOutputs();

 private:
  void track(const SourceFrame& f);
  void reviseTrajectory(const std::vector<vo::RevisedPose>& revised);
  void finishChain();
  Isometry anchor(const SourceFrame& f, const Isometry& T_odometry_camera);
  void finishStages();

  const PipelineConfig& config_;
  filters::FilterChain chain_;
  const std::string out_dir_, config_path_, gt_path_;
  const std::atomic<bool>& stop_;
  const bool realtime_;
  const Clock::time_point start_ = Clock::now();
  std::vector<datasets::StampedPose> groundtruth_, trajectory_;
  std::vector<long> trajectory_frames_;  ///< the odometry's frame number of each trajectory pose
  std::optional<Isometry> T_anchor_;
  PipelineReport report_;
  StageStats odometry_stats_;
  std::unique_ptr<mapping::StaticMapBuilder> map_;
  std::unique_ptr<datasets::RawlogWriter> filtered_;
  std::unique_ptr<TruthMasks> truth_masks_;
  FrameReader reader_;
  std::unique_ptr<MapStage> map_stage_;
  Observers observers_;
};

MappingRun::MappingRun(const PipelineConfig& config, filters::FilterChain chain, const std::string& input,
                       const std::string& out_dir, const std::string& config_path, const std::atomic<bool>& stop)
    : config_(config),
      chain_(std::move(chain)),
      out_dir_(out_dir),
      config_path_(config_path),
      gt_path_(groundTruthPath(config.dataset, input)),
      stop_(stop),
      realtime_(config.playback.mode == "realtime"),
      reader_({input, config.camera, config.dataset.repeat, config.dataset.first_frame, realtime_,
               config.playback.rate, static_cast<std::size_t>(config.playback.frame_queue), config.sensors,
               config.distortion, config.dataset.depth_radial_bias, config.output.filtered_rawlog,
               config.label_masks},
              stop, start_) {
  namespace fs = std::filesystem;
  if (!gt_path_.empty()) groundtruth_ = datasets::readGroundTruth(gt_path_, config.dataset.groundtruth_frame);
  if (config.dataset.anchor_to_groundtruth && groundtruth_.empty())
    throw AppError(config_path + ": [Dataset] anchor_to_groundtruth needs a groundtruth file");
  fs::create_directories(out_dir);
  const OutputOptions& output = config.output;
  if (output.map) {
    map_ = std::make_unique<mapping::StaticMapBuilder>(config.map);
    map_stage_ = std::make_unique<MapStage>(*map_, realtime_, static_cast<std::size_t>(config.playback.map_queue));
  }
  if (output.filtered_rawlog)
    filtered_ = std::make_unique<datasets::RawlogWriter>((fs::path(out_dir) / "filtered.rawlog").string());
  // Test and benchmark concerns, off the pipeline's path.
  const std::string masks_dir = (fs::path(input) / "masks").string();
  if (fs::is_directory(masks_dir)) {
    truth_masks_ = std::make_unique<TruthMasks>(masks_dir);
    observers_.push_back(std::make_unique<GroundTruthScorer>(
        *truth_masks_, config.map, groundtruth_, map_ && config.dataset.anchor_to_groundtruth));
  }
  if (output.overlay_every > 0)
    observers_.push_back(std::make_unique<OverlayWriter>(out_dir, output.overlay_every, truth_masks_.get()));
  if (output.memory_every > 0)
    observers_.push_back(std::make_unique<MemorySampler>(out_dir, output.memory_every, map_stage_.get()));
  if (output.tracking_log) observers_.push_back(std::make_unique<TrackingLog>(out_dir));
  if (output.match_log) observers_.push_back(std::make_unique<MatchLog>(out_dir));
  if (config.playback.progress && isatty(fileno(stderr)))
    observers_.push_back(std::make_unique<ProgressLine>(reader_.sizeHint(), start_, realtime_));
}

void MappingRun::play() {
  reader_.start();
  const int max_frames = config_.dataset.max_frames;
  while (max_frames == 0 || report_.frames < static_cast<std::size_t>(max_frames)) {
    const auto f = reader_.next();
    if (!f) break;
    track(*f);
  }
  finishChain();
  finishStages();
}

/// Odometry (the filter chain), trajectory, map job, observers for one frame.
void MappingRun::track(const SourceFrame& f) {
  const auto t0 = Clock::now();
  // The rawlog's other objects read before this frame pass on first, in order.
  if (filtered_)
    for (const auto& object : reader_.takeObjectsUpTo(f.index)) filtered_->objectRead(object);
  auto obs = datasets::observationOf(f.frame);
  filters::FilterContext ctx;
  ctx.frame_index = f.index;
  if (!filters::applyChain(chain_, *obs, ctx)) {  // decimated
    if (filtered_) filtered_->drop(*obs);
    return;
  }
  const vo::FrameTracking& tracking = *filters::trackingOf(ctx);  // the chain was checked to set it
  const Isometry T_world_camera = anchor(f, tracking.T_world_camera);
  trajectory_.push_back({f.frame.stamp, T_world_camera});
  trajectory_frames_.push_back(tracking.frame_number);
  reviseTrajectory(tracking.revised);
  // The map thread gets its own mask: the chain may reuse its buffer for the next frame.
  if (map_stage_ && tracking.tracked())
    map_stage_->submit({f.frame, ctx.dynamic_mask.clone(), T_world_camera, tracking.new_keyframe});
  if (filtered_) filtered_->write(*obs);
  const double seconds = secondsSince(t0);
  odometry_stats_.busy_s += seconds;
  ++odometry_stats_.items;
  report_.addFrame(tracking, seconds * 1000.0);
  const double lag = realtime_ ? secondsSince(start_) - f.due_s : 0.0;
  if (realtime_) report_.lag_s.push_back(lag);
  if (tracking.state == vo::TrackingState::Lost)
    std::cerr << "gmc-rgbd-mapping: frame " << f.index << " (" << f.frame.name << ") lost: " << tracking.lost_reason
              << "\n";
  const FrameEvent event{f, tracking, ctx.dynamic_mask, report_, lag};
  for (auto& o : observers_) o->onFrame(event);
}

/// Poses revised later (lost frames bridged, a rejoined map's frames, smoothed ones): the
/// trajectory keeps the revised ones. Frame numbers increase, so they are found by bisection.
void MappingRun::reviseTrajectory(const std::vector<vo::RevisedPose>& revised) {
  for (const auto& r : revised) {
    const auto it = std::lower_bound(trajectory_frames_.begin(), trajectory_frames_.end(), r.frame_number);
    if (it != trajectory_frames_.end() && *it == r.frame_number)
      trajectory_[static_cast<size_t>(it - trajectory_frames_.begin())].pose = *T_anchor_ * r.T_world_camera;
  }
}

/// The input has ended (or was stopped): the revisions the chain held back, e.g. the
/// last frames' smoothed poses.
void MappingRun::finishChain() {
  filters::FilterContext ctx;
  filters::finishChain(chain_, ctx);
  const auto* revised = filters::finalRevisionsOf(ctx);
  if (revised && T_anchor_) reviseTrajectory(*revised);
}

/// [Dataset] anchor_to_groundtruth: the first frame's odometry pose is put on its
/// ground-truth pose (maps comparable with a simulated scene).
Isometry MappingRun::anchor(const SourceFrame& f, const Isometry& T_odometry_camera) {
  if (!T_anchor_) {
    T_anchor_ = Isometry::Identity();
    if (config_.dataset.anchor_to_groundtruth) {
      const auto gt = datasets::interpolatePose(groundtruth_, f.frame.stamp);
      if (!gt) throw AppError(gt_path_ + ": no ground-truth pose near the first frame");
      T_anchor_ = *gt * T_odometry_camera.inverse();
    }
  }
  return *T_anchor_ * T_odometry_camera;
}

/// Ends the reader (after [Dataset] max_frames, frames it read ahead are discarded) and
/// lets the map insert what is queued; collects the stages' counters.
void MappingRun::finishStages() {
  reader_.finish();
  report_.dropped = reader_.dropped();
  report_.skipped = reader_.skipped();
  report_.stages.push_back({"source", reader_.stats().items, reader_.stats().busy_s});
  report_.stages.push_back({"odometry", odometry_stats_.items, odometry_stats_.busy_s});
  const auto rq = reader_.queueStats();
  report_.queues.push_back({"frames", rq.capacity, rq.high_water});
  if (!map_stage_) return;
  map_stage_->finish();
  report_.map_skipped = map_stage_->skipped();
  report_.setMapTimes(map_stage_->insertMs());
  report_.stages.push_back({"map", map_stage_->stats().items, map_stage_->stats().busy_s});
  const auto mq = map_stage_->queueStats();
  report_.queues.push_back({"map", mq.capacity, mq.high_water});
}

const PipelineReport& MappingRun::writeOutputs() {
  namespace fs = std::filesystem;
  report_.wall_seconds = secondsSince(start_);
  report_.peak_rss_mb = peakResidentMemoryMb();
  report_.interrupted = stop_;
  for (auto& o : observers_) o->onEnd(report_, map_.get());
  datasets::writeTumTrajectory((fs::path(out_dir_) / "trajectory_tum.txt").string(), trajectory_);
  datasets::writeBaseTrajectory((fs::path(out_dir_) / "trajectory_base_tum.txt").string(), trajectory_,
                                reader_.baseCamera());
  if (map_) {
    map_->writeBinary((fs::path(out_dir_) / "map.bt").string());
    report_.map = map_->stats();
    report_.has_map = true;
  }
  if (filtered_) {
    for (const auto& object : reader_.takeObjectsUpTo(SIZE_MAX)) filtered_->objectRead(object);
    filtered_->close();
  }
  datasets::writeTextAtomic((fs::path(out_dir_) / "summary.json").string(), report_.toJson());
  return report_;
}

}  // namespace

int RgbdMappingApp::run() {
  if (print_config_) return printEffectiveConfig(config_path_, overrides_);
  stop_requested_ = false;
  auto ini = cfg::loadIniFile(config_path_);
  cfg::applyOverrides(ini, overrides_);
  const PipelineConfig config = loadPipelineConfig(ini, config_path_);
  MappingRun pipeline(config, filters::buildChain(ini, config_path_, {filters::kTracking}), input_path_, out_dir_,
                      config_path_,
                      stop_requested_);
  {
    const SignalGuard signals;
    pipeline.play();
  }
  const PipelineReport& report = pipeline.writeOutputs();
  std::cout << report.toText();
  if (report.frames == 0) throw AppError(input_path_ + ": no frame could be processed");
  return 0;
}

}  // namespace gmc::apps
