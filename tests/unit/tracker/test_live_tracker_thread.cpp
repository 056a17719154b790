// The tracker thread under ThreadSanitizer (label threads): it starts and
// stops cleanly (also mid-stream and when its source ends), publishes every
// pose into the PoseSlot while readers load it, and recenter() can be called
// from another thread. No timing is asserted.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <mutex>
#include <atomic>
#include <thread>
#include <vector>

#include "earshot/tracker/live/live_tracker.hpp"
#include "earshot/tracker/send/send_spec.hpp"
#include "earshot/tracker/sources/osc_pose.hpp"
#include "earshot/tracker/sources/sim_source.hpp"
#include "earshot/tracker/sources/udp_pose_source.hpp"

using namespace earshot::tracker;
using earshot::HeadPose;
using earshot::PoseSlot;

namespace {

std::unique_ptr<FrameSource> sim(long frames, Pacing pacing = Pacing::as_fast_as_possible) {
  SimSourceConfig c;
  c.sim.motion = MotionProfile::walk;  // the walk over the box set below
  c.sim.seed = 3;
  c.sim.yaw_max_deg = 25;
  c.frames = frames;
  c.pacing = pacing;
  c.faults = {{Fault::Kind::vanish, 50, 40}, {Fault::Kind::garbage, 120, 5}};
  return std::make_unique<SimSource>(Camera::with_focal(1280.0), LedModel::thesis(), c);
}

}  // namespace

// An endless real-time source: only stop() or the destructor ends the thread.
// Started means it publishes; stopped means running() is false, the status
// says so without an error, and nothing is published after stop() returns;
// every publication reached the callback. A thread that never stops hangs
// the test (ctest's timeout), one that never starts spins below.
TEST(LiveTrackerThread, StartsAndStopsCleanly) {
  for (int i = 0; i < 5; ++i) {
    PoseSlot slot;
    std::atomic<std::uint64_t> calls{0};
    {
      LiveTracker t(sim(-1, Pacing::real_time), slot, LiveConfig{}, [&](const HeadPose&) { calls.fetch_add(1); });
      EXPECT_TRUE(t.running());
      while (slot.load().sequence < 3) std::this_thread::yield();  // started: poses arrive
      if (i % 2) {
        t.stop();
        EXPECT_FALSE(t.running());
        const auto st = t.status();
        EXPECT_FALSE(st.running);
        EXPECT_TRUE(st.error.empty()) << st.error;
        EXPECT_GE(st.frames, 3u);
        const std::uint64_t last = slot.load().sequence;
        t.stop();  // idempotent
        std::this_thread::yield();
        EXPECT_EQ(slot.load().sequence, last) << "a pose published after stop()";
      }
    }  // the destructor requests stop and joins
    EXPECT_GE(slot.load().sequence, 3u);
    EXPECT_EQ(calls.load(), slot.load().sequence) << "a publication that missed the callback";
  }
}

TEST(LiveTrackerThread, PublishesEveryPoseWhileReadersRead) {
  PoseSlot slot;
  constexpr long kFrames = 400;
  std::atomic<bool> done{false};
  std::atomic<long> backwards{0}, nonfinite{0};
  // Readers that have seen the last publication: the tracker can publish all
  // its frames before a reader is first scheduled, so each reader reads on
  // until it has seen the slot's final pose, and every run checks at least it.
  std::atomic<std::uint64_t> end_sequence{~std::uint64_t{0}};
  std::atomic<int> saw_end{0};
  // Each reader keeps a sample of what it loaded, checked afterwards against
  // what was published: a torn pose would not match its sequence number.
  std::array<std::vector<HeadPose>, 2> samples;
  std::vector<std::thread> readers;
  for (auto& sample : samples)
    readers.emplace_back([&] {
      std::uint64_t last = 0;
      bool counted = false;
      while (!done.load(std::memory_order_acquire)) {
        const HeadPose p = slot.load();
        if (!p.finite()) nonfinite.fetch_add(1);
        if (p.sequence < last) backwards.fetch_add(1);
        if (p.sequence != last && sample.size() < 5000) sample.push_back(p);
        last = p.sequence;
        if (!counted && p.sequence == end_sequence.load()) {
          counted = true;
          saw_end.fetch_add(1);
        }
      }
    });
  std::vector<HeadPose> seen;  // written by the tracker thread only, read after stop
  {
    LiveTracker t(sim(kFrames), slot, LiveConfig{}, [&](const HeadPose& p) { seen.push_back(p); });
    std::thread recenterer([&] {
      for (int i = 0; i < 10; ++i) {
        t.recenter();
        (void)t.status();
        std::this_thread::yield();
      }
    });
    recenterer.join();
    while (t.running()) std::this_thread::yield();  // the source ends by itself
    const auto st = t.status();
    EXPECT_FALSE(st.running);
    EXPECT_TRUE(st.error.empty()) << st.error;
    EXPECT_EQ(st.frames, static_cast<std::uint64_t>(kFrames));
    EXPECT_GT(st.rejected_dots, 0u);
  }
  end_sequence = slot.load().sequence;  // the tracker has stopped: the slot is final
  while (saw_end.load() < static_cast<int>(readers.size())) std::this_thread::yield();
  done = true;
  for (auto& r : readers) r.join();
  EXPECT_EQ(backwards.load(), 0);
  EXPECT_EQ(nonfinite.load(), 0);
  // One publication per frame plus the final "ended" note, in order.
  ASSERT_EQ(seen.size(), static_cast<std::size_t>(kFrames + 1));
  for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i].sequence, i + 1);
  EXPECT_EQ(slot.load().sequence, seen.size());
  std::size_t checked = 0;
  for (const auto& sample : samples)
    for (const HeadPose& p : sample) {
      if (p.sequence == 0) continue;  // the slot's initial pose
      const HeadPose& q = seen[p.sequence - 1];
      EXPECT_TRUE(p.t == q.t && p.position == q.position && p.orientation == q.orientation && p.state == q.state)
          << "torn pose at sequence " << p.sequence;
      ++checked;
    }
  EXPECT_GT(checked, 0u);
}

TEST(LiveTrackerThread, ASourceThatThrowsStopsTheThreadWithItsMessage) {
  class Failing final : public FrameSource {
   public:
    SourceEvent next(std::chrono::milliseconds) override { throw std::runtime_error("no Wii Remote found"); }
    [[nodiscard]] std::string describe() const override { return "failing"; }
  };
  PoseSlot slot;
  LiveTracker t(std::make_unique<Failing>(), slot);
  while (t.running()) std::this_thread::yield();
  EXPECT_EQ(t.status().error, "no Wii Remote found");
}

// LiveConfig::send: the tracker thread sends what it publishes (the poses a
// recording writes), thinned to the spec's rate on the steady clock however
// fast the source runs (a simulator as fast as possible). The test's own
// receiver reads Earshot's format back: every pose received is one the
// thread published, in order. The bound on the count is the cap's guarantee
// over the tracker's whole life (rate x lifetime + the bucket), not a timing
// guess.
TEST(LiveTrackerThread, SendsThePosesItPublishesAtMostAtItsRate) {
  UdpPoseSource rx("osc", 0, std::string("127.0.0.1"), OscPoseDecoder::packet_decoder());
  LiveConfig cfg;
  cfg.send = {parse_send_spec("osc:" + std::to_string(rx.port()) + ",format=earshot,rate=50")};
  std::mutex m;
  std::vector<HeadPose> published;
  published.reserve(4000);
  PoseSlot slot;
  std::uint64_t sent = 0;
  const auto start = std::chrono::steady_clock::now();
  double lifetime_s = 0;
  {
    LiveTracker t(sim(3000), slot, cfg, [&](const HeadPose& p) {
      std::lock_guard lock(m);
      published.push_back(p);
    });
    while (t.running()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    t.stop();
    lifetime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_EQ(t.senders().senders().size(), 1u);
    const auto c = t.senders().senders()[0]->counters();
    sent = c.sent;
    EXPECT_EQ(c.failed, 0u);
  }
  std::vector<HeadPose> received;
  for (int i = 0; i < 400 && received.size() < sent; ++i) {  // bounded: at most 400 waits of 10 ms
    const SourceEvent e = rx.next(std::chrono::milliseconds(10));
    if (const auto* p = std::get_if<HeadPose>(&e)) received.push_back(*p);
  }
  std::lock_guard lock(m);
  ASSERT_GE(published.size(), 3000u);
  EXPECT_GE(sent, 1u);
  EXPECT_LE(static_cast<double>(sent), 50.0 * lifetime_s + 1.5) << published.size() << " published in " << lifetime_s << " s";
  EXPECT_LT(sent, published.size() / 2) << "a source faster than the cap is thinned";
  EXPECT_EQ(rx.dropped(), 0u) << rx.last_error();
  ASSERT_GE(received.size(), 1u);
  // Each received pose is a published one (float32 on the wire), in order.
  const auto same = [](const HeadPose& a, const HeadPose& b) {
    return (to_eigen(a.position) - to_eigen(b.position)).norm() < 1e-5 &&
           to_eigen(a.orientation).angularDistance(to_eigen(b.orientation)) < 1e-5;
  };
  std::size_t at = 0;
  for (const HeadPose& r : received) {
    while (at < published.size() && !same(r, published[at])) ++at;
    EXPECT_LT(at, published.size()) << "a received pose that was never published";
  }
}

// Recordings: one row per camera frame, from the first (time 0, not a note's
// row), each with the state the pipeline gave it, and the beacon's camera-
// frame pose whenever the tracker has one.
TEST(LiveTrackerThread, GivesEveryFrameToTheRecordingFromTheFirst) {
  PoseSlot slot;
  std::vector<LiveTracker::FrameRow> rows;  // written by the tracker thread, read after it is joined
  {
    LiveTracker t(sim(300), slot, LiveConfig{}, {}, [&rows](const LiveTracker::FrameRow& r) { rows.push_back(r); });
    while (t.running()) std::this_thread::yield();
  }
  ASSERT_EQ(rows.size(), 300u);  // garbage frames too: lost rows
  EXPECT_EQ(rows.front().listener.t, 0.0);
  long lost = 0, with_camera = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (i > 0) {
      EXPECT_GT(rows[i].listener.t, rows[i - 1].listener.t);
    }
    lost += rows[i].listener.state == earshot::PoseState::lost;
    with_camera += rows[i].camera.has_value();
    if (rows[i].camera) {
      EXPECT_GT(rows[i].camera->t.z(), 100.0);  // absolute, mm from the camera
    }
  }
  EXPECT_GT(lost, 0);  // the 40 frames the beacon vanished
  EXPECT_EQ(with_camera, static_cast<long>(rows.size()));
}
