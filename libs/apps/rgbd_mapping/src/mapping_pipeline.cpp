#include "gmc/apps/mapping_pipeline.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <iostream>

namespace gmc::apps {

// ---------------------------------------------------------------- FrameReader

FrameReader::FrameReader(Options options, const std::atomic<bool>& stop, Clock::time_point start)
    : options_(std::move(options)),
      stop_(stop),
      start_(start),
      source_(datasets::openRgbdSource(options_.input, options_.camera, options_.sensors, options_.distortion,
                                                 options_.label_masks)),
      depth_bias_(options_.depth_radial_bias),
      size_hint_(source_->sizeHint()),
      queue_(options_.queue_capacity) {
  if (options_.pass_objects) source_->setObjectSink(&objects_);
}

void FrameReader::ObjectLog::objectRead(const mrpt::serialization::CSerializable::Ptr& object) {
  const std::lock_guard<std::mutex> lock(mutex_);
  objects_.push_back({object, next_frame.load()});
}

std::vector<mrpt::serialization::CSerializable::Ptr> FrameReader::ObjectLog::takeUpTo(std::size_t index) {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::vector<mrpt::serialization::CSerializable::Ptr> out;
  while (!objects_.empty() && (ended || objects_.front().frame_index <= index)) {
    out.push_back(objects_.front().object);
    objects_.pop_front();
  }
  return out;
}

std::vector<mrpt::serialization::CSerializable::Ptr> FrameReader::takeObjectsUpTo(std::size_t index) {
  return objects_.takeUpTo(index);
}

FrameReader::~FrameReader() { finish(); }

void FrameReader::start() { thread_ = std::thread([this] { loop(); }); }

void FrameReader::finish() {
  queue_.close();
  if (thread_.joinable()) thread_.join();
}

std::optional<SourceFrame> FrameReader::next() {
  auto item = queue_.pop();
  if (!item) {
    finish();
    if (error_) std::rethrow_exception(error_);
  }
  return item;
}

void FrameReader::loop() {
  try {
    SourceFrame f;
    while (!stop_ && !queue_.closed()) {
      const auto t0 = Clock::now();
      if (!readNext(f)) break;
      stats_.busy_s += secondsSince(t0);
      ++stats_.items;
      pace(f);
      if (!options_.realtime) {
        if (!queue_.push(std::move(f))) break;  // closed by the consumer
      } else {
        // A camera does not wait: a full queue loses its oldest frame.
        dropped_ += queue_.pushOrEvict(std::move(f), [](const SourceFrame&) { return false; });
      }
      f = SourceFrame();
    }
  } catch (...) {
    error_ = std::current_exception();
  }
  objects_.ended = true;
  queue_.close();
}

/// The next frame at or after [Dataset] first_frame; later passes ([Dataset] repeat)
/// reopen the input and shift stamps past the previous pass.
bool FrameReader::readNext(SourceFrame& out) {
  while (!stop_) {
    bool have = false;
    objects_.next_frame = index_;
    try {
      have = source_->next(out.frame);
    } catch (const datasets::FrameReadError& e) {
      std::cerr << "gmc-rgbd-mapping: warning: skipping " << e.what() << "\n";
      ++skipped_;
      continue;
    }
    if (!have && pass_ + 1 < options_.repeat && pass_first_stamp_ >= 0) {
      ++pass_;
      stamp_shift_ += last_stamp_ - pass_first_stamp_ + frame_interval_;
      pass_first_stamp_ = -1;
      // Later passes are the same recording again: their objects are not passed on twice.
      source_ = datasets::openRgbdSource(options_.input, options_.camera, options_.sensors, options_.distortion,
                                                 options_.label_masks);
      continue;
    }
    if (!have) return false;
    depth_bias_.apply(out.frame);
    if (pass_first_stamp_ < 0) pass_first_stamp_ = out.frame.stamp;
    else frame_interval_ = std::max(1e-3, out.frame.stamp - last_stamp_);
    last_stamp_ = out.frame.stamp;
    out.recorded_stamp = out.frame.stamp;
    out.frame.stamp += stamp_shift_;
    out.pass = pass_;
    out.index = index_++;
    if (static_cast<int>(out.index) >= options_.first_frame) return true;
  }
  return false;
}

/// Realtime: waits until the frame's time (its stamp from the first frame's, / rate).
void FrameReader::pace(SourceFrame& f) {
  if (!options_.realtime) return;
  if (first_stamp_ < 0) first_stamp_ = f.frame.stamp;
  f.due_s = (f.frame.stamp - first_stamp_) / options_.rate;
  const double now = secondsSince(start_);
  if (now < f.due_s) std::this_thread::sleep_for(std::chrono::duration<double>(f.due_s - now));
}

// ---------------------------------------------------------------- MapStage

MapStage::MapStage(InsertFn insert, NodesFn nodes, bool realtime, std::size_t queue_capacity)
    : insert_(std::move(insert)), nodes_(std::move(nodes)), realtime_(realtime), queue_(queue_capacity) {
  thread_ = std::thread([this] { loop(); });
}

MapStage::MapStage(mapping::StaticMapBuilder& map, bool realtime, std::size_t queue_capacity)
    : MapStage([&map](const MapJob& j) { return map.insertFrame(j.frame, j.dynamic_mask, j.T_world_camera); },
               [&map] { return map.tree().size(); }, realtime, queue_capacity) {}

MapStage::~MapStage() {
  queue_.close();
  if (thread_.joinable()) thread_.join();
}

void MapStage::rethrowError() {
  if (!failed_) return;
  queue_.close();
  if (thread_.joinable()) thread_.join();
  std::rethrow_exception(error_);
}

void MapStage::submit(MapJob job) {
  rethrowError();
  if (!realtime_) {
    if (!queue_.push(std::move(job))) rethrowError();
    return;
  }
  // Keep the newest: a skip takes the oldest queued frame that is not a keyframe.
  skipped_ += queue_.pushOrEvict(std::move(job), [](const MapJob& j) { return !j.keyframe; });
}

void MapStage::finish() {
  queue_.close();
  if (thread_.joinable()) thread_.join();
  if (error_) std::rethrow_exception(error_);
}

void MapStage::loop() {
  // Realtime: when the cores are short, the odometry goes first (Linux: per-thread nice).
  if (realtime_) {
    const auto tid = static_cast<id_t>(::syscall(SYS_gettid));
    errno = 0;
    const int nice = ::getpriority(PRIO_PROCESS, tid);
    if (errno == 0) ::setpriority(PRIO_PROCESS, tid, std::min(nice + 5, 19));
  }
  try {
    while (auto job = queue_.pop()) {
      const auto t0 = Clock::now();
      const bool inserted = insert_(*job);
      const double s = secondsSince(t0);
      stats_.busy_s += s;
      ++stats_.items;
      if (inserted) insert_ms_.push_back(s * 1000.0);
      tree_nodes_ = nodes_();
    }
  } catch (...) {
    error_ = std::current_exception();
    failed_ = true;
    queue_.close();  // a waiting submit() returns and rethrows
  }
}

}  // namespace gmc::apps
