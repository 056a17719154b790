// PoseSlot: never a torn or out-of-order pose, with a writer at 1 kHz and
// readers hammering the slot. Run under ThreadSanitizer in CI (label threads).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "earshot/pose_slot.hpp"

using earshot::HeadPose;
using earshot::PoseSlot;
using earshot::PoseState;

namespace {

/// A pose whose every field is derived from k, so a mix of two poses shows.
HeadPose pose_of(std::uint64_t k) {
  HeadPose p;
  const double x = static_cast<double>(k);
  p.t = x * 1e-3;
  p.position = {x, 2 * x, 3 * x};
  const double a = 1e-3 * x;
  p.orientation = {std::cos(a), std::sin(a), 0.0, 0.0};
  p.state = k % 2 ? PoseState::tracking : PoseState::predicted;
  return p;
}

bool consistent(const HeadPose& p) {
  if (p.sequence == 0) return true;  // the initial pose
  const HeadPose q = pose_of(p.sequence);
  return p.t == q.t && p.position == q.position && p.orientation == q.orientation && p.state == q.state;
}

}  // namespace

TEST(PoseSlot, RefusesNonFinitePoses) {
  PoseSlot slot;
  HeadPose p = pose_of(1);
  p.position[1] = NAN;
  EXPECT_FALSE(slot.publish(p));
  p = pose_of(1);
  p.orientation[0] = INFINITY;
  EXPECT_FALSE(slot.publish(p));
  EXPECT_EQ(slot.load().sequence, 0u);
  EXPECT_TRUE(slot.publish(pose_of(1)));
  EXPECT_EQ(slot.load().sequence, 1u);
  EXPECT_TRUE(consistent(slot.load()));
}

namespace {
#if defined(__SANITIZE_THREAD__)
#define EARSHOT_UNDER_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define EARSHOT_UNDER_TSAN 1
#endif
#endif
#ifdef EARSHOT_UNDER_TSAN
// ThreadSanitizer judges the memory model on every access and needs no
// volume; ten million of its loads would take minutes.
constexpr long kReads = 500'000;
#else
// Counting torn reads needs volume: collisions with the writer are rare.
constexpr long kReads = 10'000'000;
#endif

/// Writer at `period` (zero: as fast as it can) against two readers doing
/// kReads loads in all; counts torn and out-of-order reads.
void stress(std::chrono::microseconds period) {
  PoseSlot slot;
  constexpr int kReaders = 2;
  std::atomic<long> reads{0};
  std::atomic<bool> stop{false};
  std::atomic<long> torn{0}, backwards{0};

  std::thread writer([&] {
    // 1 kHz, like a fast tracker; k is the sequence the slot will assign.
    auto next = std::chrono::steady_clock::now();
    for (std::uint64_t k = 1; !stop.load(std::memory_order_relaxed); ++k) {
      slot.publish(pose_of(k));
      if (period.count() == 0) continue;
      next += period;
      std::this_thread::sleep_until(next);
    }
  });
  std::vector<std::thread> readers;
  for (int r = 0; r < kReaders; ++r)
    readers.emplace_back([&] {
      std::uint64_t last = 0;
      while (reads.fetch_add(1, std::memory_order_relaxed) < kReads) {
        const HeadPose p = slot.load();
        if (!consistent(p)) torn.fetch_add(1, std::memory_order_relaxed);
        if (p.sequence < last) backwards.fetch_add(1, std::memory_order_relaxed);
        last = p.sequence;
      }
    });
  for (auto& t : readers) t.join();
  stop = true;
  writer.join();
  EXPECT_EQ(torn.load(), 0);
  EXPECT_EQ(backwards.load(), 0);
  EXPECT_GT(slot.load().sequence, 1u);  // the writer did publish meanwhile
}
}  // namespace

TEST(PoseSlot, NoTornOrOutOfOrderPoseWithWriterAt1kHz) { stress(std::chrono::milliseconds(1)); }

// The writer flat out makes collisions with readers frequent: a slot that
// could tear would show it here.
TEST(PoseSlot, NoTornOrOutOfOrderPoseWithWriterFlatOut) { stress(std::chrono::microseconds(0)); }
