#pragma once
// gmc-rgbd-mapping's stages and the threads that run them (doc/architecture.md, "Threads"):
//
//   reader thread     FrameReader: source (+ [Dataset] repeat), realtime pacing
//        | frames queue (bounded; realtime: a full queue drops its oldest frame = `dropped`)
//   calling thread    filter chain + odometry, trajectory, observers
//        | map queue (bounded; realtime: a full queue skips a frame = `map_skipped`)
//   map thread        MapStage: StaticMapBuilder::insertFrame
//
// Unpaced (as_fast_as_possible) both queues wait instead of dropping: every frame is
// tracked and every tracked frame inserted, in order, so outputs are deterministic.
#include <atomic>
#include <chrono>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "gmc/apps/bounded_queue.h"
#include "gmc/datasets/camera.h"
#include "gmc/datasets/frame.h"
#include "gmc/datasets/rawlog_stream.h"
#include "gmc/datasets/source.h"
#include "gmc/datasets/undistort.h"
#include "gmc/mapping/static_map.h"

namespace gmc::apps {

/// A frame as read, with where it is in the run.
struct SourceFrame {
  datasets::RgbdFrame frame;   ///< stamp shifted past earlier passes ([Dataset] repeat)
  double recorded_stamp = 0;   ///< the stamp in the input (masks, ground truth)
  std::size_t index = 0;       ///< position in the input, counted over all passes
  int pass = 0;
  double due_s = 0;            ///< realtime: when the camera delivered it (s from start)
};

/// A tracked frame on its way into the map.
struct MapJob {
  datasets::RgbdFrame frame;
  cv::Mat dynamic_mask;
  Isometry T_world_camera = Isometry::Identity();
  bool keyframe = false;
};

/// Counters of one stage (summary.json "stages").
struct StageStats {
  std::size_t items = 0;
  double busy_s = 0;  ///< time spent working (not waiting on a queue)
  double ratePerBusySecond() const { return busy_s > 0 ? items / busy_s : 0.0; }
};

struct QueueStats {
  std::size_t capacity = 0, high_water = 0;
};

using Clock = std::chrono::steady_clock;
inline double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Reads the input on its own thread into a bounded queue.
class FrameReader {
 public:
  struct Options {
    std::string input;
    PinholeCamera camera;
    int repeat = 1, first_frame = 0;
    bool realtime = false;
    double rate = 1.0;
    std::size_t queue_capacity = 4;
    datasets::SensorSelection sensors;   ///< the camera to track ([Filters] sensor_label)
    datasets::LensDistortion distortion;  ///< removed from TUM folders' frames
    double depth_radial_bias = 0;        ///< removed from every frame's depth (undistort.h)
    bool pass_objects = false;           ///< keep every rawlog object for takeObjectsUpTo()
    datasets::LabelMasks label_masks;    ///< per-frame pixel labels of TUM folders
  };
  /// A rawlog object read, tagged with the index of the frame read after it.
  struct PassedObject {
    mrpt::serialization::CSerializable::Ptr object;
    std::size_t frame_index = 0;
  };
  /// `stop`: checked before every frame (signals, or the consumer has enough).
  FrameReader(Options options, const std::atomic<bool>& stop, Clock::time_point start);
  ~FrameReader();  ///< closes the queue and joins
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;

  void start();
  /// Next frame in order; nothing at the end (the reader has then ended). Rethrows the
  /// reader's error (InputError).
  std::optional<SourceFrame> next();
  /// Stops the reader (a blocked push returns) and joins; frames still queued are
  /// discarded. Counters are final after this or after next() returned nothing.
  void finish();
  std::size_t sizeHint() const { return size_hint_; }
  /// Objects of the rawlog (first pass) read before frame `index` and not taken yet, in
  /// the order read (all of them after the reader ended). Thread-safe: they are read on
  /// the reader's thread and written, in order, by the consumer's.
  std::vector<mrpt::serialization::CSerializable::Ptr> takeObjectsUpTo(std::size_t index);
  /// T_base_camera of the camera read last; valid once the reader has ended.
  std::optional<Isometry> baseCamera() const { return source_->baseCamera(); }
  std::size_t dropped() const { return dropped_; }  ///< realtime, evicted unprocessed
  std::size_t skipped() const { return skipped_; }  ///< unreadable frames
  StageStats stats() const { return stats_; }
  QueueStats queueStats() const { return {queue_.capacity(), queue_.highWater()}; }

 private:
  /// Collects the objects the source reads (on the reader's thread).
  class ObjectLog : public datasets::RawlogObjectSink {
   public:
    void objectRead(const mrpt::serialization::CSerializable::Ptr& object) override;
    std::vector<mrpt::serialization::CSerializable::Ptr> takeUpTo(std::size_t index);
    std::atomic<std::size_t> next_frame{0};
    std::atomic<bool> ended{false};

   private:
    std::mutex mutex_;
    std::deque<PassedObject> objects_;
  };

  void loop();
  bool readNext(SourceFrame& out);
  void pace(SourceFrame& f);

  Options options_;
  const std::atomic<bool>& stop_;
  Clock::time_point start_;
  std::unique_ptr<datasets::RgbdSource> source_;
  datasets::RadialDepthBias depth_bias_;  ///< used by the reader thread only
  ObjectLog objects_;
  std::size_t size_hint_ = 0;
  BoundedQueue<SourceFrame> queue_;
  std::thread thread_;
  std::exception_ptr error_;
  // Written by the reader thread only; read after join (or as atomics).
  std::atomic<std::size_t> dropped_{0}, skipped_{0};
  StageStats stats_;
  // Repeat bookkeeping.
  std::size_t index_ = 0;
  int pass_ = 0;
  double stamp_shift_ = 0, pass_first_stamp_ = -1, last_stamp_ = 0, frame_interval_ = 1.0 / 30.0;
  double first_stamp_ = -1;
};

/// Inserts tracked frames into the map on its own thread.
class MapStage {
 public:
  /// Inserts one job; false when the map skipped it by its own rule (insert_every_n_frames).
  using InsertFn = std::function<bool(const MapJob&)>;
  /// Map size after an insertion (for memory samples).
  using NodesFn = std::function<std::size_t()>;
  MapStage(InsertFn insert, NodesFn nodes, bool realtime, std::size_t queue_capacity);
  /// Into `map`, which must outlive the stage.
  MapStage(mapping::StaticMapBuilder& map, bool realtime, std::size_t queue_capacity);
  ~MapStage();  ///< closes the queue and joins
  MapStage(const MapStage&) = delete;
  MapStage& operator=(const MapStage&) = delete;

  /// Unpaced: waits for room. Realtime: never waits; a full queue skips its oldest
  /// non-keyframe job (else its oldest), counted in skipped(). Rethrows the map's error.
  void submit(MapJob job);
  /// Inserts what is queued, then joins; rethrows the map thread's error.
  void finish();
  std::size_t skipped() const { return skipped_; }
  /// Map nodes after the last insertion (safe to read from any thread).
  std::size_t treeNodes() const { return tree_nodes_; }
  const std::vector<double>& insertMs() const { return insert_ms_; }  ///< after finish()
  StageStats stats() const { return stats_; }                        ///< after finish()
  QueueStats queueStats() const { return {queue_.capacity(), queue_.highWater()}; }

 private:
  void loop();
  void rethrowError();

  InsertFn insert_;
  NodesFn nodes_;
  const bool realtime_;
  BoundedQueue<MapJob> queue_;
  std::thread thread_;
  std::exception_ptr error_;
  std::atomic<bool> failed_{false};
  std::atomic<std::size_t> tree_nodes_{0};
  std::size_t skipped_ = 0;  // the submitting thread's
  std::vector<double> insert_ms_;
  StageStats stats_;
};

}  // namespace gmc::apps
