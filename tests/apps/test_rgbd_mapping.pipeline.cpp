// The concurrent stages of gmc-rgbd-mapping: queue policies (unpaced: every item in
// order; realtime: a full queue evicts and the producer never waits) and the map stage.
// Also built under ThreadSanitizer (doc/robustness.md, GMC_SANITIZE=thread).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

#include "gmc/apps/bounded_queue.h"
#include "gmc/apps/mapping_pipeline.h"

namespace {

using gmc::apps::BoundedQueue;
using gmc::apps::MapJob;
using gmc::apps::MapStage;

/// A one-shot gate: wait() blocks until open().
class Gate {
 public:
  void open() {
    {
      std::lock_guard<std::mutex> lock(m_);
      open_ = true;
    }
    cv_.notify_all();
  }
  void wait() {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait(lock, [&] { return open_; });
  }

 private:
  std::mutex m_;
  std::condition_variable cv_;
  bool open_ = false;
};

std::vector<int> closeAndDrain(BoundedQueue<int>& q) {
  q.close();
  std::vector<int> left;
  while (auto v = q.pop()) left.push_back(*v);
  return left;
}

TEST(BoundedQueue, BlockingPushDeliversEveryItemInOrderToASlowConsumer) {
  BoundedQueue<int> q(3);
  std::vector<int> got;
  std::thread consumer([&] {
    std::mt19937 rng(1);
    while (auto v = q.pop()) {
      got.push_back(*v);
      if (rng() % 4 == 0) std::this_thread::sleep_for(std::chrono::microseconds(300));
    }
  });
  for (int i = 0; i < 300; ++i) ASSERT_TRUE(q.push(i));
  q.close();
  consumer.join();
  ASSERT_EQ(got.size(), 300u);
  for (int i = 0; i < 300; ++i) EXPECT_EQ(got[static_cast<size_t>(i)], i);
  EXPECT_EQ(q.highWater(), 3u);
}

// No consumer at all: a push that waited for room would never return.
TEST(BoundedQueue, PushOrEvictNeverWaitsAndKeepsTheNewest) {
  BoundedQueue<int> q(3);
  size_t evicted = 0;
  for (int i = 0; i < 10; ++i) evicted += q.pushOrEvict(i, [](int) { return false; });
  EXPECT_EQ(evicted, 7u);
  EXPECT_EQ(closeAndDrain(q), (std::vector<int>{7, 8, 9}));
}

TEST(BoundedQueue, EvictionTakesThePreferredOldestFirstElseTheOldest) {
  BoundedQueue<int> q(3);
  const auto odd = [](int v) { return v % 2 == 1; };  // odd = "not a keyframe"
  for (int v : {0, 1, 2}) q.pushOrEvict(v, odd);
  EXPECT_EQ(q.pushOrEvict(4, odd), 1u);  // evicts 1: {0, 2, 4}
  EXPECT_EQ(q.pushOrEvict(6, odd), 1u);  // no odd left: evicts the oldest, 0
  EXPECT_EQ(closeAndDrain(q), (std::vector<int>{2, 4, 6}));
}

TEST(BoundedQueue, CloseWakesAWaitingPushAndAWaitingPop) {
  BoundedQueue<int> full(1);
  ASSERT_TRUE(full.push(1));
  bool pushed = true;
  std::thread producer([&] { pushed = full.push(2); });  // waits: no room
  BoundedQueue<int> empty(1);
  bool popped = true;
  std::thread consumer([&] { popped = empty.pop().has_value(); });  // waits: nothing
  full.close();
  empty.close();
  producer.join();
  consumer.join();
  EXPECT_FALSE(pushed);
  EXPECT_FALSE(popped);
  EXPECT_EQ(full.pop(), 1);  // what was queued before close() is still delivered
}

MapJob job(double stamp, bool keyframe) {
  MapJob j;
  j.frame.stamp = stamp;
  j.keyframe = keyframe;
  return j;
}

// Realtime: the map is stuck inside its first insertion while the odometry submits 20
// more frames; submit() must not wait (it would hang here), the queue keeps the newest
// keyframes first, and every skipped frame is counted.
TEST(MapStage, RealtimeSubmitNeverWaitsForASlowMapAndCountsSkips) {
  Gate started, release;
  std::vector<double> inserted;
  MapStage stage(
      [&](const MapJob& j) {
        if (inserted.empty()) {
          started.open();
          release.wait();
        }
        inserted.push_back(j.frame.stamp);
        return true;
      },
      [] { return size_t{0}; }, /*realtime=*/true, /*queue_capacity=*/4);
  stage.submit(job(0, false));
  started.wait();
  for (int i = 1; i <= 20; ++i) stage.submit(job(i, i % 5 == 0));  // keyframes 5, 10, 15, 20
  release.open();
  stage.finish();
  EXPECT_EQ(stage.skipped(), 16u);
  EXPECT_EQ(inserted, (std::vector<double>{0, 5, 10, 15, 20}));
  EXPECT_EQ(stage.insertMs().size(), inserted.size());
  EXPECT_EQ(stage.queueStats().high_water, 4u);
}

// Unpaced: a slow map makes the producer wait; nothing is skipped, order is kept.
TEST(MapStage, UnpacedInsertsEveryFrameInOrder) {
  std::vector<double> inserted;
  MapStage stage(
      [&](const MapJob& j) {
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        inserted.push_back(j.frame.stamp);
        return j.frame.stamp != 7;  // the map's own skip rule: not an insertion
      },
      [&] { return inserted.size(); }, /*realtime=*/false, /*queue_capacity=*/2);
  for (int i = 0; i < 60; ++i) stage.submit(job(i, false));
  stage.finish();
  ASSERT_EQ(inserted.size(), 60u);
  for (int i = 0; i < 60; ++i) EXPECT_EQ(inserted[static_cast<size_t>(i)], i);
  EXPECT_EQ(stage.skipped(), 0u);
  EXPECT_EQ(stage.insertMs().size(), 59u);
  EXPECT_EQ(stage.stats().items, 60u);
  EXPECT_EQ(stage.treeNodes(), 60u);
}

TEST(MapStage, AnInsertionErrorReachesTheSubmitterAndFinish) {
  MapStage stage([](const MapJob&) -> bool { throw std::invalid_argument("bad mask"); }, [] { return size_t{0}; },
                 /*realtime=*/false, /*queue_capacity=*/1);
  EXPECT_THROW(
      {
        for (int i = 0; i < 100; ++i) stage.submit(job(i, false));
        stage.finish();
      },
      std::invalid_argument);
}

}  // namespace
