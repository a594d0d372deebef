#pragma once
// gmc-rgbd-mapping: rawlog/TUM playback -> observation filter chain (GMC odometry and
// dynamic masks) -> OctoMap of static depth -> trajectory, map, summary.
#include <atomic>
#include <string>
#include <vector>

#include "gmc/apps/app.h"
#include "gmc/apps/pipeline_report.h"
#include "gmc/datasets/camera.h"
#include "gmc/datasets/frame.h"
#include "gmc/datasets/rawlog_stream.h"
#include "gmc/datasets/source.h"
#include "gmc/mapping/static_map.h"

#include <mrpt/config/CConfigFileBase.h>

namespace gmc::apps {

/// INI section [Dataset].
struct DatasetOptions {
  std::string camera = "fr3";  ///< fr1|fr2|fr3|bonn|custom (custom: fx, fy, cx, cy below)
  double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;
  int max_frames = 0;          ///< 0 = all
  int first_frame = 0;
  std::string groundtruth;     ///< optional TUM file; "auto" = <input>/groundtruth.txt if present
  std::string groundtruth_frame = "camera";  ///< or "bonn": marker-body poses, converted
  bool anchor_to_groundtruth = false;  ///< start the trajectory at the ground-truth pose
  std::string undistort = "auto";  ///< auto: TUM's published distortion for fr1/fr2; none
  double depth_radial_bias = 0;    ///< k of a depth read as z (1 + k r^2), divided back out
  int repeat = 1;              ///< play the input this many times (long-run tests); later
                               ///< passes get stamps shifted past the previous pass
  std::string label_masks;     ///< folder of per-frame masks given as a pixel label (TUM folders)
  std::string label_masks_name = "person";  ///< ... that label's name

  template <class V>
  void visit(V& v) {
    v.choice("camera", camera, {"fr1", "fr2", "fr3", "bonn", "custom"}, "intrinsics preset");
    v("fx", fx, 1.0, 1e5, "custom focal length x (px)");
    v("fy", fy, 1.0, 1e5, "custom focal length y (px)");
    v("cx", cx, 0.0, 1e5, "custom principal point x (px)");
    v("cy", cy, 0.0, 1e5, "custom principal point y (px)");
    v.choice("undistort", undistort, {"auto", "none"},
             "auto: remove the lens distortion TUM publishes for fr1/fr2 (folders); none: use images as they are");
    v("depth_radial_bias", depth_radial_bias, -0.5, 0.5,
      "k of the sensor's radial depth bias (depth read as z (1 + k r^2), r the normalised image radius); "
      "every reading is divided by (1 + k r^2); 0 = none (doc/datasets.md)");
    v("max_frames", max_frames, 0, 100000000, "process at most this many frames (0 = all)");
    v("first_frame", first_frame, 0, 100000000, "skip this many frames first");
    v("groundtruth", groundtruth, "TUM ground truth file, 'auto', or empty");
    v.choice("groundtruth_frame", groundtruth_frame, {"camera", "bonn"},
             "what the ground truth gives poses of: camera (TUM) or bonn (marker body, converted)");
    v("anchor_to_groundtruth", anchor_to_groundtruth,
      "start the trajectory at the first ground-truth pose (maps comparable with ground truth)");
    v("repeat", repeat, 1, 1000000, "play the input this many times (stamps shifted per pass)");
    v("label_masks", label_masks,
      "folder of the input (TUM layout) with one mask per frame, named as its RGB image, given to the scan as the "
      "pixel label label_masks_name (e.g. the generator's masks; empty = none)");
    v("label_masks_name", label_masks_name,
      "name of that pixel label ([GmcFilter] known_dynamic_labels can make it known dynamic)");
  }
};

/// INI section [Playback].
struct PlaybackOptions {
  std::string mode = "as_fast_as_possible";  ///< or "realtime" (paced by timestamps)
  double rate = 1.0;                         ///< realtime speed factor
  bool progress = true;                      ///< progress line on a terminal
  int frame_queue = 4;  ///< frames read ahead of the odometry (realtime: full = oldest dropped)
  int map_queue = 8;    ///< tracked frames waiting for the map (realtime: full = one skipped)

  template <class V>
  void visit(V& v) {
    v.choice("mode", mode, {"as_fast_as_possible", "realtime"}, "playback pacing");
    v("rate", rate, 0.01, 100.0, "realtime speed factor");
    v("progress", progress, "progress line (frame, fps, ETA, realtime lag) on a terminal");
    v("frame_queue", frame_queue, 1, 1000, "frames read ahead of the odometry");
    v("map_queue", map_queue, 1, 1000, "tracked frames waiting for the map insertion");
  }
};

/// INI section [Output].
struct OutputOptions {
  bool map = true;                 ///< build and write map.bt
  bool filtered_rawlog = false;    ///< write filtered.rawlog
  int overlay_every = 0;           ///< write overlays/<stamp>.png every N frames (0 = never)
  int memory_every = 0;            ///< memory.csv row (resident memory, map) every N frames
  bool tracking_log = false;       ///< tracking.csv: every frame's state, evidence and pose
  bool match_log = false;          ///< map_matches.csv: every frame's matches against the map

  template <class V>
  void visit(V& v) {
    v("map", map, "build the OctoMap and write map.bt");
    v("filtered_rawlog", filtered_rawlog, "write the filtered observations to filtered.rawlog");
    v("overlay_every", overlay_every, 0, 1000000, "overlay PNG every N frames (0 = none)");
    v("memory_every", memory_every, 0, 1000000,
      "memory.csv row (frame, resident MB, map nodes) every N frames (0 = none)");
    v("tracking_log", tracking_log,
      "write tracking.csv: per frame state, lost reason, matches, static evidence, pose");
    v("match_log", match_log,
      "write map_matches.csv: per frame every match against the landmark map, with the observation that placed "
      "the landmark (for scripts/match_truth.py)");
  }
};

/// The INI sections gmc-rgbd-mapping and gmc-rawlog-filter share, loaded strictly.
struct PipelineConfig {
  DatasetOptions dataset;
  PlaybackOptions playback;
  OutputOptions output;
  mapping::StaticMapOptions map;
  PinholeCamera camera;  ///< from [Dataset] camera (TUM folders; rawlogs carry their own)
  /// From [Filters] sensor_label: the camera the odometry tracks (single_camera).
  datasets::SensorSelection sensors;
  /// From [Dataset] undistort and camera: removed from frames of TUM folders.
  datasets::LensDistortion distortion;
  /// From [Dataset] label_masks and label_masks_name.
  datasets::LabelMasks label_masks;
};
/// Throws cfg::ConfigError naming the file, section and key; also rejects sections that
/// neither the apps nor the filters read.
PipelineConfig loadPipelineConfig(const mrpt::config::CConfigFileBase& ini, const std::string& source);

class RgbdMappingApp : public App {
 public:
  void initialize(const std::vector<std::string>& args) override;
  int run() override;

  /// Asks a running run() to stop: no frame is read after it; frames already read are
  /// processed and inserted (signal handlers call this).
  static void requestStop();

  const std::string& outputDir() const { return out_dir_; }

 private:
  std::string config_path_, input_path_, out_dir_;
  bool print_config_ = false;  ///< --print-config: print the effective configuration, stop
  std::vector<std::string> overrides_;
  static std::atomic<bool> stop_requested_;
};

}  // namespace gmc::apps
