#pragma once
// A bounded queue between two pipeline threads (one producer, one consumer).
//
// push() blocks while the queue is full: every item goes through, in order (unpaced
// playback). pushOrEvict() never blocks: on a full queue it first evicts a queued item
// the caller's policy chooses (realtime playback: the producer must not wait).
// close() ends the stream: pop() returns what is left, then nothing; pushes fail.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

namespace gmc::apps {

template <class T>
class BoundedQueue {
 public:
  explicit BoundedQueue(std::size_t capacity) : capacity_(capacity < 1 ? 1 : capacity) {}

  /// Waits for room; false (item dropped) when the queue is closed.
  bool push(T item) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_full_.wait(lock, [&] { return closed_ || items_.size() < capacity_; });
    if (closed_) return false;
    append(std::move(item));
    lock.unlock();
    not_empty_.notify_one();
    return true;
  }

  /// Never waits. On a full queue, evicts the first queued item (oldest first) for
  /// which `evict_first(item)` is true, else the oldest, and returns 1 (0 when there was
  /// room). Returns 0 and drops `item` when the queue is closed.
  template <class Pred>
  std::size_t pushOrEvict(T item, Pred evict_first) {
    std::size_t evicted = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (closed_) return 0;
      if (items_.size() >= capacity_) {
        auto victim = items_.begin();
        for (auto it = items_.begin(); it != items_.end(); ++it)
          if (evict_first(*it)) {
            victim = it;
            break;
          }
        items_.erase(victim);
        evicted = 1;
      }
      append(std::move(item));
    }
    not_empty_.notify_one();
    return evicted;
  }

  /// Waits for an item; nothing once the queue is closed and empty.
  std::optional<T> pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    not_empty_.wait(lock, [&] { return closed_ || !items_.empty(); });
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    lock.unlock();
    not_full_.notify_one();
    return item;
  }

  /// No more pushes; the consumer still gets what is queued. Wakes every waiter.
  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    not_full_.notify_all();
    not_empty_.notify_all();
  }

  bool closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
  }
  std::size_t capacity() const { return capacity_; }
  /// The most items ever queued at once.
  std::size_t highWater() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return high_water_;
  }

 private:
  void append(T&& item) {
    items_.push_back(std::move(item));
    if (items_.size() > high_water_) high_water_ = items_.size();
  }

  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable not_full_, not_empty_;
  std::deque<T> items_;
  std::size_t high_water_ = 0;
  bool closed_ = false;
};

}  // namespace gmc::apps
