#pragma once
// Per-run counters and per-stage timing of gmc-rgbd-mapping (summary.json).
#include <string>
#include <vector>

#include "gmc/datasets/evaluation.h"
#include "gmc/mapping/map_quality.h"
#include "gmc/mapping/static_map.h"
#include "gmc/vo/odometry.h"

namespace gmc::apps {

/// Median and 95th percentile of a series (0 when empty).
struct Percentiles {
  double median = 0, p95 = 0;
  static Percentiles of(std::vector<double> values);
};

/// Current and peak resident memory of this process in MB (Linux /proc; 0 elsewhere).
double residentMemoryMb();
double peakResidentMemoryMb();
/// Bytes the program holds from malloc (glibc's mallinfo2; 0 elsewhere), in MB: resident
/// memory minus this is the allocator's retained free memory, not a leak.
double heapInUseMb();

/// Pose observations against ground-truth masks (simulated input).
struct PosePoints {
  std::size_t points = 0, on_people = 0;
  double share() const { return points ? static_cast<double>(on_people) / static_cast<double>(points) : 0.0; }
  PosePoints& operator+=(const PosePoints& o) {
    points += o.points, on_people += o.on_people;
    return *this;
  }
};

struct PipelineReport {
  size_t frames = 0, tracked = 0, lost = 0, reanchored = 0, keyframes = 0;
  size_t lost_pose_undetermined = 0;  ///< lost although enough inliers: pose not determined
  size_t lost_background_untrusted = 0;  ///< lost: the static landmarks disagree with every hypothesis
  size_t windows_discarded = 0;  ///< keyframes whose windowed optimisation moved them implausibly far
  size_t rejoined = 0;           ///< frames that found the map left at a re-anchor ([Rejoin])
  size_t start_consensus = 0;    ///< frames that took their young map's start consensus ([StartConsensus])
  size_t dropped = 0;   ///< realtime: frames the odometry never processed (it was behind)
  size_t skipped = 0;   ///< frames that could not be read
  size_t map_inserts = 0;
  size_t map_skipped = 0;  ///< realtime: tracked frames the map stage had no time for
  /// Per stage (source, odometry, map): items handled and time spent on them.
  struct Stage {
    std::string name;
    size_t items = 0;
    double busy_s = 0;
  };
  std::vector<Stage> stages;
  /// Bounded queues between the stages: capacity and most items ever queued.
  struct Queue {
    std::string name;
    size_t capacity = 0, high_water = 0;
  };
  std::vector<Queue> queues;
  std::vector<double> lag_s;  ///< realtime: per frame, end of its processing - its due time
  double wall_seconds = 0;
  double peak_rss_mb = 0;  ///< the process's peak resident memory (VmHWM)
  bool interrupted = false;
  bool has_map = false;
  mapping::MapStats map;
  bool has_map_quality = false;
  mapping::MapQuality map_quality;
  std::vector<double> frontend_ms, guess_ms, gmc_ms, refine_ms, odometry_ms, mask_ms, map_ms, total_ms;
  size_t static_matches = 0, dynamic_matches = 0;
  /// Against ground-truth masks (simulated input): matched keypoints with a decision
  /// (Static or Dynamic), Dynamic vs on a person. Undecided keypoints are not counted.
  bool has_mask_score = false;
  datasets::BinaryScore mask_score;
  /// The per-pixel dynamic mask handed to the map vs the ground-truth masks, over the
  /// pixels with depth (what the map could insert).
  datasets::BinaryScore pixel_mask_score;
  /// The observations that held tracked poses, and those on people: standing people are
  /// static while they stand, and a pose resting on them moves when they sway.
  PosePoints pose_points;

  /// One frame through the chain and odometry; `pipeline_ms`: its time on that stage.
  void addFrame(const vo::FrameTracking& t, double pipeline_ms);
  /// The map stage's insertion times (ms per frame that reached the tree).
  void setMapTimes(std::vector<double> insert_ms);
  std::string toJson() const;
  std::string toText() const;
};

}  // namespace gmc::apps
