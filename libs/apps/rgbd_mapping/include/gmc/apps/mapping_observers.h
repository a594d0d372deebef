#pragma once
// What gmc-rgbd-mapping does beside the pipeline, as observers of each tracked frame (on
// the odometry thread) and of the run's end (after every stage has finished): the
// progress line, overlays, scores against the simulator's ground truth, memory samples.
#include <chrono>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "gmc/apps/mapping_pipeline.h"
#include "gmc/apps/pipeline_report.h"
#include "gmc/datasets/evaluation.h"
#include "gmc/datasets/tum.h"
#include "gmc/mapping/map_quality.h"
#include "gmc/vo/odometry.h"

namespace gmc::apps {

struct FrameEvent {
  const SourceFrame& source;
  const vo::FrameTracking& tracking;
  const cv::Mat& dynamic_mask;
  const PipelineReport& report;  ///< counters including this frame
  double lag_s = 0;              ///< realtime: processed this long after the camera gave it
};

class FrameObserver {
 public:
  virtual ~FrameObserver() = default;
  virtual void onFrame(const FrameEvent& event) = 0;
  /// After the map stage has finished: `map` is complete (null without a map).
  virtual void onEnd(PipelineReport& /*report*/, const mapping::StaticMapBuilder* /*map*/) {}
};
using Observers = std::vector<std::unique_ptr<FrameObserver>>;

/// Of a tracked frame's pose points (`keypoint_in_pose`), how many lie on a person in
/// the ground-truth `mask` (255 on people). Lost frames count nothing: their pose is a
/// prediction.
PosePoints countPosePoints(const vo::FrameTracking& tracking, const cv::Mat& mask);

/// The simulator's ground-truth mask of the current frame (masks/<stamp>.png), read at
/// most once per frame however many observers ask.
class TruthMasks {
 public:
  explicit TruthMasks(std::string dir) : dir_(std::move(dir)) {}
  /// Throws AppError naming the frame when its mask is missing.
  const cv::Mat& of(const SourceFrame& f);

 private:
  std::string dir_;
  std::size_t index_ = static_cast<std::size_t>(-1);
  cv::Mat mask_;
};

/// "\rframe i/n  fps  ETA  state  lag" on stderr (a terminal only).
class ProgressLine : public FrameObserver {
 public:
  ProgressLine(std::size_t total_hint, Clock::time_point start, bool realtime)
      : total_(total_hint), start_(start), realtime_(realtime) {}
  void onFrame(const FrameEvent& e) override;
  void onEnd(PipelineReport&, const mapping::StaticMapBuilder*) override;

 private:
  std::size_t total_;
  Clock::time_point start_;
  bool realtime_;
};

/// overlays/<stamp>.png every `every` frames: keypoints by label, dynamic mask, and the
/// ground-truth outline on simulated input (`truth` may be null).
class OverlayWriter : public FrameObserver {
 public:
  OverlayWriter(std::string out_dir, int every, TruthMasks* truth);
  void onFrame(const FrameEvent& e) override;

 private:
  std::string dir_;
  int every_;
  TruthMasks* truth_;
};

/// Simulated input, first pass: dynamic keypoints and mask pixels against the truth
/// masks; with a map anchored to ground truth, ghost voxels and static coverage too.
class GroundTruthScorer : public FrameObserver {
 public:
  GroundTruthScorer(TruthMasks& truth, const mapping::StaticMapOptions& map_options,
                    std::vector<datasets::StampedPose> groundtruth, bool score_map);
  void onFrame(const FrameEvent& e) override;
  void onEnd(PipelineReport& report, const mapping::StaticMapBuilder* map) override;

 private:
  TruthMasks& truth_;
  double max_range_;
  std::vector<datasets::StampedPose> groundtruth_;
  std::unique_ptr<mapping::GroundTruthVoxels> voxels_;
  datasets::BinaryScore keypoints_, pixels_;
  PosePoints pose_points_;
};

/// memory.csv / memory.png: resident memory, heap in use and map nodes every N frames.
class MemorySampler : public FrameObserver {
 public:
  MemorySampler(std::string out_dir, int every, const MapStage* map);
  void onFrame(const FrameEvent& e) override;
  void onEnd(PipelineReport&, const mapping::StaticMapBuilder*) override;

  struct Sample {
    double frame, resident_mb, map_nodes, heap_mb;
  };

 private:
  std::string dir_;
  std::size_t every_;
  const MapStage* map_;
  std::vector<Sample> samples_;
};

/// A CSV log of the run, filled frame by frame and written whole (atomically) at its end.
class CsvLog : public FrameObserver {
 public:
  void onEnd(PipelineReport&, const mapping::StaticMapBuilder*) override;

 protected:
  /// `path`: the file written at the end; `header`: its first line, without newline.
  CsvLog(std::string path, const char* header);
  std::ostringstream csv_;

 private:
  std::string path_;
};

/// tracking.csv: one row per frame with the odometry's state, why it is lost, the
/// evidence behind the decision (matches, static landmarks, inliers, position sigma) and
/// the pose, to see where and why a run goes wrong (next to gmc-eval's ate.per_pose).
class TrackingLog : public CsvLog {
 public:
  explicit TrackingLog(const std::string& out_dir);
  void onFrame(const FrameEvent& e) override;
};

/// map_matches.csv: one row per match of a frame against the landmark map, with the
/// matched point and the observation that placed the landmark (each in its camera's
/// frame), GMC's label, whether it went into the pose and whether it is an inlier of the
/// refinement's result: scripts/match_truth.py judges them against a ground truth.
class MatchLog : public CsvLog {
 public:
  explicit MatchLog(const std::string& out_dir);
  void onFrame(const FrameEvent& e) override;
};

}  // namespace gmc::apps
