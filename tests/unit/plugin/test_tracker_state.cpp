// esGetTrackerState (ABI 1.1): the tracker's state, rate, dots and message,
// through the linked API (no tracker, the simulated camera, a Wii Remote that
// is not there, a replay that ends) and, for a Wii Remote that disconnects
// mid-run, through a scripted HID session mapped by the same function the
// library uses. Misuse returns error codes. No timing is asserted: each
// state is waited for (at most ~10 s) and then checked.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <string>
#include <thread>

#include "../tracker/scripted_hid.hpp"
#include "earshot/earshot.h"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/live/live_tracker.hpp"
#include "earshot/tracker/sim/simulator.hpp"
#include "earshot/tracker/sources/wiimote_source.hpp"
#include "tracker_state.hpp"
#include "tracker_world.hpp"

namespace {

using World = earshot::plugin_tests::TrackerWorld;

bool has(const char* text, const char* part) { return std::string(text).find(part) != std::string::npos; }

TEST(TrackerState, NoTrackerAndMisuse) {
  World t;
  EStrackerstate s = t.state();
  EXPECT_EQ(s.state, ES_TRACKER_NONE);
  EXPECT_EQ(s.running, ES_FALSE);
  EXPECT_EQ(s.dot_count, 0u);
  EXPECT_TRUE(has(s.message, "no tracker")) << s.message;

  EXPECT_EQ(esGetTrackerState(t.w, nullptr), ES_INVALID_VALUE);
  s.size = sizeof s - 4;  // an older, smaller struct than this library's
  EXPECT_EQ(esGetTrackerState(t.w, &s), ES_INVALID_VALUE);
  EXPECT_TRUE(has(esGetErrorMessage(t.w), "size")) << esGetErrorMessage(t.w);
  s.size = sizeof s;
  EXPECT_EQ(esGetTrackerState(0, &s), ES_INVALID_WORLD);
  EXPECT_EQ(esGetTrackerState(t.w ^ 0x100u, &s), ES_INVALID_WORLD);  // another generation
  std::thread([&] { EXPECT_EQ(esGetTrackerState(t.w, &s), ES_WRONG_THREAD); }).join();

  ESworld gone = 0;
  {
    World d;
    gone = d.w;
  }
  EXPECT_EQ(esGetTrackerState(gone, &s), ES_INVALID_WORLD);
  // Through the table too.
  const ESproctable* es = esGetProcTable(ES_ABI_VERSION_MAJOR);
  ASSERT_NE(es, nullptr);
  EXPECT_EQ(es->GetTrackerState(gone, &s), ES_INVALID_WORLD);
  EXPECT_EQ(es->GetTrackerState(t.w, &s), ES_OK);
}

// The simulated camera (100 Hz): tracking, about its rate, four dots in the
// image with the four LED labels.
TEST(TrackerState, SimulatedCameraTracksWithFourLabelledDots) {
  World t;
  ASSERT_EQ(esAttachTracker(t.w, "sim"), ES_OK) << esGetErrorMessage(t.w);
  const bool seen = t.wait_for([](const EStrackerstate& s) {
    if (s.state != ES_TRACKER_TRACKING || s.dot_count != 4 || s.rate_hz < 50 || s.rate_hz > 150) return false;
    std::set<int> labels;
    for (ESuint i = 0; i < s.dot_count; ++i) labels.insert(s.dots[i].label);
    return labels == std::set<int>{0, 1, 2, 3};
  });
  const EStrackerstate s = t.state();
  ASSERT_TRUE(seen) << "state 0x" << std::hex << s.state << std::dec << ", " << s.dot_count << " dots, "
                    << s.rate_hz << " Hz: " << s.message;
  EXPECT_EQ(s.running, ES_TRUE);
  EXPECT_STREQ(s.source, "sim");
  EXPECT_GT(s.frames, 0u);
  for (ESuint i = 0; i < s.dot_count; ++i) {
    EXPECT_GE(s.dots[i].x, 0.0f);
    EXPECT_LT(s.dots[i].x, float(ES_CAMERA_WIDTH));
    EXPECT_GE(s.dots[i].y, 0.0f);
    EXPECT_LT(s.dots[i].y, float(ES_CAMERA_HEIGHT));
    EXPECT_EQ(s.dots[i].size, -1) << "the simulator has no blob sizes";
  }
  ASSERT_EQ(esAttachTracker(t.w, nullptr), ES_OK);
  EXPECT_EQ(t.state().state, ES_TRACKER_NONE);
}

// `wiimote` where there is none (the build machines have no Bluetooth): not
// an error but a state, with how to pair one; the audio renders on.
TEST(TrackerState, NoWiiRemoteIsSearchingWithHowToPair) {
  World t;
  ASSERT_EQ(esAttachTracker(t.w, "wiimote"), ES_OK) << esGetErrorMessage(t.w);
  EStrackerstate s{};
  const bool seen = t.wait_for([&](const EStrackerstate& x) {
    s = x;
    return x.state != ES_TRACKER_SEARCHING || has(x.message, "Wii Remote");  // first: "waiting for the first frame"
  });
  ASSERT_TRUE(seen);
  if (s.state == ES_TRACKER_CONNECTED || s.state == ES_TRACKER_TRACKING) GTEST_SKIP() << "a Wii Remote is here";
  EXPECT_EQ(s.state, ES_TRACKER_SEARCHING) << s.message;
  EXPECT_TRUE(has(s.message, "Wii Remote")) << s.message;
  EXPECT_TRUE(has(s.message, "bluetoothctl") || has(s.message, "udev") || has(s.message, "permission"))
      << "says how to get one connected: " << s.message;
  EXPECT_EQ(s.running, ES_TRUE) << "keeps looking";
  EXPECT_EQ(s.dot_count, 0u);
}

// A replay that ends: lost, saying so, and the head eases back to straight.
TEST(TrackerState, ReplayThatEndsIsLostAndTheHeadEasesToStraight) {
  const auto path = std::filesystem::temp_directory_path() / ("earshot-ts-" + std::to_string(getpid()) + ".csv");
  {
    using namespace earshot::tracker;
    SimulatorConfig c;
    c.seed = 5;
    c.angular_speed_deg_s = 120;
    Simulator sim(Camera::with_focal(1280.0), LedModel::thesis(), c);
    std::ofstream f(path);
    DotsCsvWriter wr(f, false);
    for (int i = 0; i < 80; ++i) wr.write(sim.next());
  }
  World t;
  ASSERT_EQ(esAttachTracker(t.w, ("replay:" + path.string()).c_str()), ES_OK) << esGetErrorMessage(t.w);
  ASSERT_EQ(esRecenter(t.w), ES_OK);  // the first pose is straight ahead; the walk turns away from it
  double turned = 0;
  const bool tracked = t.wait_for([&](const EStrackerstate& s) {
    turned = std::max(turned, t.head_angle_deg());
    return s.state == ES_TRACKER_LOST;
  });
  ASSERT_TRUE(tracked);
  const EStrackerstate s = t.state();
  EXPECT_TRUE(has(s.message, "end of")) << s.message;
  EXPECT_TRUE(has(s.message, "eases")) << s.message;
  EXPECT_EQ(s.dot_count, 0u);
  EXPECT_GT(turned, 1.0) << "the replayed head should have turned";
  EXPECT_TRUE(t.wait_for([&](const EStrackerstate&) { return t.head_angle_deg() < 0.1; }))
      << "the head stays at " << t.head_angle_deg() << " deg";
  std::filesystem::remove(path);
}

// A Wii Remote session from the remote's side (scripted HID): IR frames with
// four dots and their sizes, then the remote goes away: disconnected, with
// the message, mapped by the library's own function.
TEST(TrackerState, WiiRemoteThatDisconnectsMidRun) {
  using namespace earshot::tracker;
  using namespace earshot::tracker::testing;
  using K = Step::Kind;
  std::deque<Step> s;
  s.push_back({K::expect_write, {0x11, 0x10}});
  s.push_back({K::expect_write, {0x17, 0x00, 0x00, 0x00, 0x16, 0x00, 0x0A}});
  Bytes cal{0x21, 0x00, 0x00, 0x90, 0x00, 0x16, 0x80, 0x80, 0x80, 0x00, 0x9A, 0x9A, 0x9A, 0x00, 0x00};
  unsigned sum = 0x55;
  for (std::size_t i = 6; i < cal.size(); ++i) sum += cal[i];
  cal.push_back(static_cast<std::uint8_t>(sum));
  cal.resize(22, 0);
  s.push_back({K::reply, cal});
  for (const auto& w : wiimote::ir_init_sequence(wiimote::IrMode::extended, wiimote::IrSensitivity::level3)) {
    s.push_back({K::expect_write, Bytes(w.view().begin(), w.view().end())});
    if (wiimote::expects_acknowledgement(w)) s.push_back({K::reply, {0x22, 0x00, 0x00, w.id(), 0x00}});
  }
  // 150 IR reports (dots at (100,200) (300,200) (100,400) (300,400), size 2 each), then gone.
  // (Each costs a solve that fails: slow under sanitizers, so not many.)
  const Bytes ir{0x33, 0x00, 0x00, 0x80, 0x80, 0x9A, 0x64, 0xC8, 0x02, 0x2C, 0xC8, 0x12,
                 0x64, 0x90, 0x42, 0x2C, 0x90, 0x52};
  for (int i = 0; i < 150; ++i) s.push_back({K::reply, ir});
  s.push_back({K::gone, {}});

  // Paced: one report per 5 ms, as a remote streams (100 Hz in its life).
  class Paced final : public HidTransport {
   public:
    explicit Paced(std::deque<Step> script) : hid_(std::move(script)) {}
    std::vector<HidDeviceInfo> enumerate(std::uint16_t v, std::span<const std::uint16_t> p) override {
      return hid_.enumerate(v, p);
    }
    void open(const HidDeviceInfo& d) override { hid_.open(d); }
    void close() override { hid_.close(); }
    bool write(std::span<const std::uint8_t> r) override { return hid_.write(r); }
    int read(std::span<std::uint8_t> b, std::chrono::milliseconds t) override {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      return hid_.read(b, t);
    }
    ScriptedHid hid_;
  };
  WiimoteOptions opt;
  opt.retry_s = 0.05;
  earshot::PoseSlot slot;
  LiveConfig cfg;
  cfg.keep_running_after_end = true;
  auto transport = std::make_unique<Paced>(s);
  const ScriptedHid& script = transport->hid_;
  LiveTracker tracker(std::make_unique<WiimoteSource>(std::move(transport), opt), slot, cfg);
  auto poll = [&](const std::function<bool(const EStrackerstate&)>& ok, EStrackerstate& out) {
    for (int i = 0; i < 6000; ++i) {  // at most a minute (sanitizers are slow)
      const auto st = tracker.status();
      out.size = sizeof out;
      earshot::plugin::fill_tracker_state(&st, out);
      if (ok(out)) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  };
  EStrackerstate st{};
  ASSERT_TRUE(poll([](const EStrackerstate& x) { return x.dot_count == 4; }, st)) << st.message;
  EXPECT_NE(st.state, ES_TRACKER_SEARCHING);  // connected: the dots are not the LED model's, so maybe no pose
  EXPECT_FLOAT_EQ(st.dots[0].x, 100.0f);
  EXPECT_FLOAT_EQ(st.dots[0].y, 200.0f);
  EXPECT_FLOAT_EQ(st.dots[3].x, 300.0f);
  EXPECT_FLOAT_EQ(st.dots[3].y, 400.0f);
  for (ESuint i = 0; i < 4; ++i) {
    EXPECT_EQ(st.dots[i].size, 2);
    EXPECT_EQ(st.dots[i].slot, static_cast<ESint>(i));
  }
  EXPECT_STREQ(st.source, "wiimote");
  ASSERT_TRUE(poll([](const EStrackerstate& x) { return x.state == ES_TRACKER_DISCONNECTED; }, st))
      << "state 0x" << std::hex << st.state << ": " << st.message;
  EXPECT_TRUE(has(st.message, "disconnected")) << st.message;
  EXPECT_TRUE(has(st.message, "1+2")) << st.message;
  EXPECT_EQ(st.dot_count, 0u);
  EXPECT_EQ(st.running, ES_TRUE) << "keeps trying to reconnect";
  tracker.stop();
  for (const auto& e : script.errors) ADD_FAILURE() << e;
}

// The mapping on its own: each state of the pipeline and the link.
TEST(TrackerState, StatusMapping) {
  using earshot::tracker::LiveTracker;
  LiveTracker::Status st;
  st.source = "wiimote";
  EStrackerstate out{};
  auto map = [&] {
    out.size = sizeof out;
    earshot::plugin::fill_tracker_state(&st, out);
    return out.state;
  };
  EXPECT_EQ(map(), ES_TRACKER_SEARCHING);
  st.link = LiveTracker::Link::searching;
  st.note = earshot::tracker::no_wiimote_message();
  EXPECT_EQ(map(), ES_TRACKER_SEARCHING);
  EXPECT_TRUE(has(out.message, "no Wii Remote found")) << out.message;
  st.link = LiveTracker::Link::connected;
  st.note = "Wii Remote connected (/dev/hidraw3)";
  EXPECT_EQ(map(), ES_TRACKER_CONNECTED);
  st.state = earshot::PoseState::tracking;
  EXPECT_EQ(map(), ES_TRACKER_TRACKING);
  st.state = earshot::PoseState::predicted;
  EXPECT_EQ(map(), ES_TRACKER_TRACKING);
  st.state = earshot::PoseState::lost;
  st.camera = true;
  EXPECT_EQ(map(), ES_TRACKER_LOST);
  EXPECT_TRUE(has(out.message, "LEDs")) << out.message;
  st.link = LiveTracker::Link::disconnected;
  st.note = "Wii Remote disconnected; reconnecting (press 1+2 on the remote)";
  EXPECT_EQ(map(), ES_TRACKER_DISCONNECTED);
  st.ended = true;
  st.error = "read failed";
  EXPECT_EQ(map(), ES_TRACKER_LOST);
  EXPECT_TRUE(has(out.message, "read failed")) << out.message;
  st.running = false;
  st.rate_hz = 99;
  map();
  EXPECT_EQ(out.rate_hz, 0.0f) << "a stopped tracker has no rate";
  // Long texts are cut and NUL-ended.
  st.source = std::string(500, 's');
  st.error = std::string(1000, 'e');
  map();
  EXPECT_EQ(std::string(out.source).size(), sizeof out.source - 1);
  EXPECT_EQ(std::string(out.message).size(), sizeof out.message - 1);
  // Dots: non-finite ones are left out; the rest keep their slot.
  st.dots[1] = LiveTracker::Dot{10, 20, 3, 2};
  st.dots[2] = LiveTracker::Dot{std::nan(""), 20, 3, 1};
  map();
  ASSERT_EQ(out.dot_count, 1u);
  EXPECT_EQ(out.dots[0].slot, 1);
  EXPECT_EQ(out.dots[0].label, 2);
  EXPECT_EQ(out.dots[0].size, 3);
}

}  // namespace
