// The built plugin binary (earshot.lv2/earshot.so), driven through its LV2
// descriptor by a small host of our own, where the real hosts (lilv's tools,
// jalv) cannot look: run() neither allocates nor locks even while it asks
// for a new SOFA set and a tracker; the worker's answers are adopted; the
// notify port reports the set; state saves and restores the set and the
// tracker spec. The real hosts are in lv2_hosts (tests/unit/lv2/lv2_hosts.cmake).
#include <arpa/inet.h>
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <lv2/atom/forge.h>
#include <lv2/atom/util.h>
#include <lv2/core/lv2.h>
#include <lv2/patch/patch.h>
#include <lv2/state/state.h>
#include <lv2/urid/urid.h>
#include <lv2/worker/worker.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "binaural_cues.hpp"
#include "../scratch_path.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double kRate = 48000.0;
constexpr std::uint32_t kFrames = 256;
constexpr std::uint32_t kMaxFrames = 4096;  // the longest run_frames
constexpr const char* kUri = "urn:earshot:lv2:panner";

enum Port : std::uint32_t {
  kIn, kOutLeft, kOutRight, kControl, kNotify, kAzimuth, kElevation, kDistance, kGain, kDistanceModel, kRoom,
  kReverbSend, kTracking, kTrackerSource, kRecenter, kYawOffset, kPitchOffset, kRollOffset, kLatency, kHeadYaw,
  kHeadPitch, kHeadRoll, kEnabled, kInvertYaw, kInvertPitch, kInvertRoll, kRotationOrder, kOscPort, kOpentrackPort,
  kPortCount
};

/// URIs to numbers; reserved up front so run()'s lookups never allocate.
struct UridMap {
  std::vector<std::string> uris;
  LV2_URID_Map map{this, [](LV2_URID_Map_Handle h, const char* uri) -> LV2_URID {
                     auto* self = static_cast<UridMap*>(h);
                     for (std::size_t i = 0; i < self->uris.size(); ++i)
                       if (self->uris[i] == uri) return static_cast<LV2_URID>(i + 1);
                     self->uris.emplace_back(uri);
                     return static_cast<LV2_URID>(self->uris.size());
                   }};
  LV2_URID operator()(const char* uri) { return map.map(this, uri); }
};

/// Worker messages in preallocated slots (schedule_work is called in run()).
struct Queue {
  std::array<std::array<std::uint8_t, 8192>, 16> slots{};
  std::array<std::uint32_t, 16> sizes{};
  std::size_t count = 0;
  bool push(std::uint32_t size, const void* data) {
    if (count == slots.size() || size > slots[0].size()) return false;
    std::memcpy(slots[count].data(), data, size);
    sizes[count++] = size;
    return true;
  }
};

class Host {
 public:
  explicit Host(const fs::path& library) {
    dl_ = dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!dl_) throw std::runtime_error(dlerror());
    auto fn = reinterpret_cast<LV2_Descriptor_Function>(dlsym(dl_, "lv2_descriptor"));
    if (!fn) throw std::runtime_error("no lv2_descriptor");
    desc_ = fn(0);
    // Then the Ambisonic decoders, orders 1-5 (test_lv2_ambi_plugin.cpp), and no more.
    if (!desc_ || std::string(desc_->URI) != kUri || fn(6) != nullptr) throw std::runtime_error("bad descriptor");
    for (std::uint32_t i = 1; i <= 5; ++i)
      if (!fn(i) || std::string(fn(i)->URI) != "urn:earshot:lv2:ambi-binaural-o" + std::to_string(i))
        throw std::runtime_error("bad Ambisonic descriptor");
    worker_ = static_cast<const LV2_Worker_Interface*>(desc_->extension_data(LV2_WORKER__interface));
    state_ = static_cast<const LV2_State_Interface*>(desc_->extension_data(LV2_STATE__interface));
    map_.uris.reserve(256);
  }
  ~Host() {
    if (handle_) desc_->cleanup(handle_);
    if (dl_) dlclose(dl_);
  }

  /// `features`: the host's own array (null: ours, map and worker).
  bool instantiate(const LV2_Feature* const* features = nullptr, bool ours = true) {
    schedule_ = {this, [](LV2_Worker_Schedule_Handle h, std::uint32_t size, const void* data) {
                   return static_cast<Host*>(h)->jobs_.push(size, data) ? LV2_WORKER_SUCCESS : LV2_WORKER_ERR_NO_SPACE;
                 }};
    map_feature_ = {LV2_URID__map, &map_.map};
    schedule_feature_ = {LV2_WORKER__schedule, &schedule_};
    features_ = {&map_feature_, &schedule_feature_, nullptr};
    handle_ = desc_->instantiate(desc_, kRate, "", ours ? features_.data() : features);
    if (!handle_) return false;
    for (std::uint32_t p = 0; p < kPortCount; ++p) {
      if (p == kIn || p == kOutLeft || p == kOutRight || p == kControl || p == kNotify) continue;
      desc_->connect_port(handle_, p, &controls_[p]);
    }
    controls_[kDistance] = 1.0f;
    controls_[kDistanceModel] = 2.0f;
    controls_[kReverbSend] = -12.0f;
    controls_[kEnabled] = 1.0f;
    controls_[kOscPort] = 9000.0f;
    controls_[kOpentrackPort] = 4242.0f;
    desc_->connect_port(handle_, kIn, in_.data());
    desc_->connect_port(handle_, kOutLeft, left_.data());
    desc_->connect_port(handle_, kOutRight, right_.data());
    desc_->connect_port(handle_, kControl, control_.data());
    desc_->connect_port(handle_, kNotify, notify_.data());
    clear_control();
    desc_->activate(handle_);
    return true;
  }

  float& control(Port p) { return controls_[p]; }

  /// One run() of kFrames; input noise; the output appended to `out`, the input to `in`.
  void run(std::vector<float>* out_left = nullptr, std::vector<float>* out_right = nullptr,
           std::vector<float>* in = nullptr) {
    run_frames(kFrames);
    if (in) in->insert(in->end(), in_.begin(), in_.begin() + kFrames);
    if (out_left) out_left->insert(out_left->end(), left_.begin(), left_.begin() + kFrames);
    if (out_right) out_right->insert(out_right->end(), right_.begin(), right_.begin() + kFrames);
  }

  /// One run() of `frames` (at most kMaxFrames), input noise.
  void run_frames(std::uint32_t frames) {
    for (std::uint32_t i = 0; i < frames; ++i) in_[i] = noise_(rng_);
    auto* n = reinterpret_cast<LV2_Atom_Sequence*>(notify_.data());
    n->atom.type = 0;
    n->atom.size = static_cast<std::uint32_t>(notify_.size() * sizeof(notify_[0]) - sizeof(LV2_Atom));
    desc_->run(handle_, frames);
    clear_control();
  }

  /// Puts a patch:Set of `property` to a path or string into the next run().
  void patch_set(const char* property, const std::string& value, const char* type) {
    LV2_Atom_Forge forge;
    lv2_atom_forge_init(&forge, &map_.map);
    lv2_atom_forge_set_buffer(&forge, reinterpret_cast<std::uint8_t*>(control_.data()),
                              control_.size() * sizeof(control_[0]));
    LV2_Atom_Forge_Frame seq, obj;
    lv2_atom_forge_sequence_head(&forge, &seq, 0);
    lv2_atom_forge_frame_time(&forge, 0);
    lv2_atom_forge_object(&forge, &obj, 0, map_(LV2_PATCH__Set));
    lv2_atom_forge_key(&forge, map_(LV2_PATCH__property));
    lv2_atom_forge_urid(&forge, map_(property));
    lv2_atom_forge_key(&forge, map_(LV2_PATCH__value));
    lv2_atom_forge_typed_string(&forge, map_(type), value.c_str(), static_cast<std::uint32_t>(value.size()));
    lv2_atom_forge_pop(&forge, &obj);
    lv2_atom_forge_pop(&forge, &seq);
  }

  /// The worker's thread: runs the queued jobs; their answers wait for deliver().
  void work() {
    Queue now = jobs_;
    jobs_.count = 0;
    for (std::size_t i = 0; i < now.count; ++i)
      worker_->work(
          handle_,
          [](LV2_Worker_Respond_Handle h, std::uint32_t size, const void* data) {
            return static_cast<Host*>(h)->answers_.push(size, data) ? LV2_WORKER_SUCCESS : LV2_WORKER_ERR_NO_SPACE;
          },
          this, now.sizes[i], now.slots[i].data());
  }
  /// The audio thread, between runs: the answers to the plugin.
  void deliver() {
    for (std::size_t i = 0; i < answers_.count; ++i)
      worker_->work_response(handle_, answers_.sizes[i], answers_.slots[i].data());
    answers_.count = 0;
  }
  [[nodiscard]] std::size_t jobs() const { return jobs_.count; }
  void activate() { desc_->activate(handle_); }

  /// The value of the newest patch:Set of `property` on the notify port, or "".
  std::string notified(const char* property) {
    const auto* seq = reinterpret_cast<const LV2_Atom_Sequence*>(notify_.data());
    std::string found;
    if (seq->atom.type != map_(LV2_ATOM__Sequence)) return found;
    LV2_ATOM_SEQUENCE_FOREACH(seq, ev) {
      const auto* obj = reinterpret_cast<const LV2_Atom_Object*>(&ev->body);
      if (obj->body.otype != map_(LV2_PATCH__Set)) continue;
      const LV2_Atom *prop = nullptr, *value = nullptr;
      lv2_atom_object_get(obj, map_(LV2_PATCH__property), &prop, map_(LV2_PATCH__value), &value, 0);
      if (prop && value && reinterpret_cast<const LV2_Atom_URID*>(prop)->body == map_(property))
        found = static_cast<const char*>(LV2_ATOM_BODY_CONST(value));
    }
    return found;
  }

  /// Saved state by URI (key -> value, type), so another host's map reads it.
  using Saved = std::map<std::string, std::pair<std::string, std::string>>;
  Saved save() {
    std::map<LV2_URID, std::pair<std::string, LV2_URID>> raw;
    state_->save(
        handle_,
        [](LV2_State_Handle h, std::uint32_t key, const void* value, std::size_t size, std::uint32_t type,
           std::uint32_t) {
          auto& m = *static_cast<std::map<LV2_URID, std::pair<std::string, LV2_URID>>*>(h);
          m[key] = {std::string(static_cast<const char*>(value), size - 1), type};
          return LV2_STATE_SUCCESS;
        },
        &raw, 0, features_.data());
    Saved s;
    for (auto& [k, v] : raw) s[map_.uris[k - 1]] = {v.first, map_.uris[v.second - 1]};
    return s;
  }
  LV2_State_Status restore(const Saved& s) {
    restoring_.clear();
    for (auto& [k, v] : s) restoring_[map_(k.c_str())] = {v.first, map_(v.second.c_str())};
    return state_->restore(
        handle_,
        [](LV2_State_Handle h, std::uint32_t key, std::size_t* size, std::uint32_t* type,
           std::uint32_t* flags) -> const void* {
          auto& m = *static_cast<std::map<LV2_URID, std::pair<std::string, LV2_URID>>*>(h);
          auto it = m.find(key);
          if (it == m.end()) return nullptr;
          *size = it->second.first.size() + 1;
          *type = it->second.second;
          *flags = LV2_STATE_IS_POD;
          return it->second.first.c_str();
        },
        &restoring_, 0, features_.data());
  }
  UridMap& urids() { return map_; }

 private:
  void clear_control() {
    auto* seq = reinterpret_cast<LV2_Atom_Sequence*>(control_.data());
    seq->atom.type = map_(LV2_ATOM__Sequence);
    seq->atom.size = sizeof(LV2_Atom_Sequence_Body);
    seq->body.unit = 0;
    seq->body.pad = 0;
  }

  void* dl_ = nullptr;
  const LV2_Descriptor* desc_ = nullptr;
  const LV2_Worker_Interface* worker_ = nullptr;
  const LV2_State_Interface* state_ = nullptr;
  LV2_Handle handle_ = nullptr;
  UridMap map_;
  std::map<LV2_URID, std::pair<std::string, LV2_URID>> restoring_;
  LV2_Worker_Schedule schedule_{};
  LV2_Feature map_feature_{}, schedule_feature_{};
  std::array<const LV2_Feature*, 3> features_{};
  Queue jobs_, answers_;
  std::array<float, kPortCount> controls_{};
  std::array<float, kMaxFrames> in_{}, left_{}, right_{};
  std::array<std::uint64_t, 1024> control_{}, notify_{};  // 8-byte aligned atom buffers
  std::mt19937 rng_{3};
  std::normal_distribution<float> noise_{0.0f, 0.1f};
};

fs::path plugin_library() { return fs::path(EARSHOT_LV2_BUNDLE) / "earshot.so"; }

/// A small SOFA set written by the test fixture tool.
fs::path make_sofa(const std::string& name) {
  const fs::path out = earshot::test::scratch_path("lv2_" + name + ".sofa");
  const std::string cmd = std::string("/usr/bin/python3 ") + EARSHOT_MAKE_SOFA + " --out '" + out.string() +
                          "' --length 64 --grid fibonacci:300";
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("make_sofa.py failed: " + cmd);
  return out;
}

double ild(const std::vector<float>& l, const std::vector<float>& r) { return earshot::analysis::ild_db(l, r); }

}  // namespace

TEST(Lv2Plugin, RunNeverAllocatesOrLocksWhileItAsksForASetAndATracker) {
  Host host(plugin_library());
  ASSERT_TRUE(host.instantiate());
  host.control(kAzimuth) = 40.0f;
  for (int i = 0; i < 4; ++i) host.run();  // warm
  const fs::path sofa = make_sofa("alloc");
  host.patch_set("urn:earshot:lv2:panner#sofa", sofa.string(), LV2_ATOM__Path);
  {
    earshot::testing::AllocationProbe probe;
    host.run();  // the set change: a job for the worker
    host.control(kTracking) = 1.0f;
    host.control(kTrackerSource) = 1.0f;  // sim
    host.control(kRoom) = 8.0f;
    host.run();  // the tracker: another job
    for (int i = 0; i < 32; ++i) {
      host.control(kAzimuth) = static_cast<float>(i * 10);
      host.control(kYawOffset) = static_cast<float>(i);
      host.run();
    }
    EXPECT_EQ(probe.count(), 0u);
    EXPECT_EQ(probe.lock_count(), 0u);
  }
  EXPECT_EQ(host.jobs(), 2u);
  {
    // The probe sees the plugin library's allocations: the worker's do count.
    earshot::testing::AllocationProbe probe;
    host.work();
    EXPECT_GT(probe.count(), 0u);
  }
  {
    earshot::testing::AllocationProbe probe;
    host.deliver();  // adopting the new panner and the tracker lease, handing the old panner back
    host.run();
    EXPECT_EQ(probe.count(), 0u);
    EXPECT_EQ(probe.lock_count(), 0u);
  }
  EXPECT_EQ(host.notified("urn:earshot:lv2:panner#sofa"), sofa.string());
  // After the crossfade (1024 frames) the old panner goes back to the worker.
  EXPECT_EQ(host.jobs(), 0u);
  {
    earshot::testing::AllocationProbe probe;
    for (int i = 0; i < 4; ++i) host.run();  // both panners run, then the fade
    EXPECT_EQ(probe.count(), 0u);
    EXPECT_EQ(probe.lock_count(), 0u);
  }
  EXPECT_EQ(host.jobs(), 1u);
  host.work();
  // Tracking off: the lease goes back to the worker too.
  host.control(kTracking) = 0.0f;
  host.run();
  EXPECT_EQ(host.jobs(), 1u);
  host.work();
  fs::remove(sofa);
}

TEST(Lv2Plugin, AzimuthAndTheYawOffsetMoveTheImage) {
  Host host(plugin_library());
  ASSERT_TRUE(host.instantiate());
  std::vector<float> l, r;
  host.control(kAzimuth) = 60.0f;
  for (int i = 0; i < 100; ++i) host.run(&l, &r);
  EXPECT_GT(ild(l, r), 6.0);
  EXPECT_EQ(host.control(kLatency), 128.0f);
  // The listener turned to face the source: straight ahead.
  l.clear();
  r.clear();
  host.control(kYawOffset) = 60.0f;
  for (int i = 0; i < 4; ++i) host.run();
  for (int i = 0; i < 100; ++i) host.run(&l, &r);
  EXPECT_LT(std::abs(ild(l, r)), 1.0);
  EXPECT_NEAR(host.control(kHeadYaw), 60.0f, 1e-3);
}

TEST(Lv2Plugin, TrackingFollowsTheSharedSimulatedHead) {
  Host host(plugin_library());
  ASSERT_TRUE(host.instantiate());
  host.control(kTracking) = 1.0f;
  host.control(kTrackerSource) = 1.0f;  // sim: a seeded random walk of the head
  host.run();
  host.work();
  host.deliver();
  float lo = 1e9f, hi = -1e9f;
  for (int i = 0; i < 300; ++i) {  // about 3 s of the simulator's walk
    host.run();
    lo = std::min(lo, host.control(kHeadYaw));
    hi = std::max(hi, host.control(kHeadYaw));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_GT(hi - lo, 1.0f) << "the head never moved";
  host.control(kTracking) = 0.0f;
  host.run();
  host.work();
}

// Two instances on the one shared simulated head, run back to back: one
// with short blocks, one with long ones. Each carries the head on to when
// its own block is heard, so the long-block instance is ahead of the other
// by the head's turn over the difference of their leads (2048 - 64 frames,
// 41 ms at 48 kHz). Without prediction both would show the same head.
TEST(Lv2Plugin, TheTrackedHeadIsPredictedToWhenTheBlockIsHeard) {
  Host shortb(plugin_library()), longb(plugin_library());
  ASSERT_TRUE(shortb.instantiate());
  ASSERT_TRUE(longb.instantiate());
  for (Host* h : {&shortb, &longb}) {
    h->control(kTracking) = 1.0f;
    h->control(kTrackerSource) = 1.0f;  // sim
    h->run();
    h->work();
    h->deliver();
  }
  constexpr std::uint32_t kShort = 64, kLong = 2048;
  const double lead_gap_s = static_cast<double>(kLong - kShort) / kRate;
  double sxy = 0.0, sxx = 0.0;  // regression through 0 of the gap on the turn rate x lead gap
  int agree = 0, moving = 0;
  double last_yaw = 0.0;
  auto last_t = std::chrono::steady_clock::now();
  for (int i = 0; i < 400; ++i) {  // about 4 s of the simulator's walk
    shortb.run_frames(kShort);
    longb.run_frames(kLong);
    const auto t = std::chrono::steady_clock::now();
    const double yaw = shortb.control(kHeadYaw), ahead = longb.control(kHeadYaw);
    const double dt = std::chrono::duration<double>(t - last_t).count();
    if (i > 0 && dt > 0.0) {
      double turn = yaw - last_yaw;  // degrees since the last step
      if (turn > 180) turn -= 360;
      if (turn < -180) turn += 360;
      const double rate = turn / dt;            // deg/s, as the short-block instance heard it
      double gap = ahead - yaw;
      if (gap > 180) gap -= 360;
      if (gap < -180) gap += 360;
      const double x = rate * lead_gap_s;       // the gap prediction makes
      sxy += x * gap;
      sxx += x * x;
      if (std::abs(rate) > 20.0) {
        ++moving;
        if ((gap > 0) == (rate > 0)) ++agree;
      }
    }
    last_yaw = yaw;
    last_t = t;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_GT(moving, 20) << "the simulated head hardly turned";
  EXPECT_GT(agree, moving * 3 / 4) << agree << " of " << moving << " moving steps lead in the turn's direction";
  ASSERT_GT(sxx, 0.0);
  const double slope = sxy / sxx;  // 1: the gap is the turn over the lead gap
  std::printf("lead: %.2f x the turn over the lead gap; %d of %d moving steps ahead in the turn's direction\n", slope,
              agree, moving);
  // Below 1 (0.36-0.41 measured): the turn rate is estimated from the short-block
  // instance's own steps, whose noise dilutes the fit; the filter's velocity lags
  // the turn a little; and a pose older than 15 ms is carried at most
  // kMaxHeadPredictionS (60 ms) ahead.
  EXPECT_GT(slope, 0.2) << "the long-block instance is not ahead of the short-block one";
  EXPECT_LT(slope, 1.6);
  for (Host* h : {&shortb, &longb}) {
    h->control(kTracking) = 0.0f;
    h->run();
    h->work();
  }
}

TEST(Lv2Plugin, StateRestoresTheSetAndTheTrackerSpec) {
  const fs::path sofa = make_sofa("state");
  Host::Saved saved;
  {
    Host host(plugin_library());
    ASSERT_TRUE(host.instantiate());
    host.patch_set("urn:earshot:lv2:panner#sofa", sofa.string(), LV2_ATOM__Path);
    host.run();
    host.work();
    host.deliver();
    host.patch_set("urn:earshot:lv2:panner#tracker", "osc:9123", LV2_ATOM__String);
    host.run();
    saved = host.save();
  }
  EXPECT_EQ(saved["urn:earshot:lv2:panner#sofa"], std::make_pair(sofa.string(), std::string(LV2_ATOM__Path)));
  EXPECT_EQ(saved["urn:earshot:lv2:panner#tracker"], std::make_pair(std::string("osc:9123"), std::string(LV2_ATOM__String)));
  // Another host (its own URID numbers) restores it: the same state, and
  // the same output as a session that set the same things by hand.
  Host other(plugin_library());
  ASSERT_TRUE(other.instantiate());
  ASSERT_EQ(other.restore(saved), LV2_STATE_SUCCESS);
  EXPECT_EQ(other.save(), saved);
  Host by_hand(plugin_library());
  ASSERT_TRUE(by_hand.instantiate());
  by_hand.patch_set("urn:earshot:lv2:panner#sofa", sofa.string(), LV2_ATOM__Path);
  by_hand.run();
  by_hand.work();
  by_hand.deliver();
  for (int i = 0; i < 5; ++i) by_hand.run();  // the switch's warm-up and crossfade (1024 frames)
  std::vector<float> l1, r1, l2, r2;
  other.control(kAzimuth) = by_hand.control(kAzimuth) = 70.0f;
  for (int i = 0; i < 40; ++i) {
    other.run(&l1, &r1);
    by_hand.run(&l2, &r2);
  }
  // Compare the settled cues: from the 5th block on, past the FIFO and the
  // renderer's move from azimuth 0 (the warm-up ran there).
  const auto settled = [](const std::vector<float>& x) { return std::vector<float>(x.begin() + 4 * 256, x.end()); };
  EXPECT_NEAR(ild(settled(l1), settled(r1)), ild(settled(l2), settled(r2)), 0.1);
  fs::remove(sofa);
}

TEST(Lv2Plugin, AMissingSetIsLoggedAndTheOldOneKept) {
  Host host(plugin_library());
  ASSERT_TRUE(host.instantiate());
  host.control(kAzimuth) = 90.0f;
  host.patch_set("urn:earshot:lv2:panner#sofa", "/nonexistent/set.sofa", LV2_ATOM__Path);
  host.run();
  host.work();
  host.deliver();
  std::vector<float> l, r;
  for (int i = 0; i < 50; ++i) host.run(&l, &r);
  EXPECT_GT(ild(l, r), 6.0);  // still rendering with the default set
}

// A plugin must survive what real hosts hand it. Debian's lv2file passes a
// feature entry whose URI is NULL (the plugin crashed reading it, exit 139);
// others pass no array at all, or a feature without its data or function.
// Each instance still renders.
TEST(Lv2Plugin, SurvivesOddFeatureArrays) {
  UridMap map;
  map.uris.reserve(64);
  LV2_Feature null_uri{nullptr, nullptr}, map_feature{LV2_URID__map, &map.map};
  LV2_URID_Map no_function{&map, nullptr};
  LV2_Feature map_without_function{LV2_URID__map, &no_function}, map_without_data{LV2_URID__map, nullptr};
  LV2_Worker_Schedule no_schedule{nullptr, nullptr};
  LV2_Feature schedule_without_function{LV2_WORKER__schedule, &no_schedule};
  const std::vector<std::vector<const LV2_Feature*>> arrays{
      {&null_uri, &map_feature, nullptr},                     // lv2file's
      {&map_feature, &null_uri, &null_uri, nullptr},
      {&map_without_data, &schedule_without_function, nullptr},
      {&map_without_function, nullptr},
      {nullptr},
  };
  for (std::size_t i = 0; i <= arrays.size(); ++i) {
    Host host(plugin_library());
    const bool null_array = i == arrays.size();
    ASSERT_TRUE(host.instantiate(null_array ? nullptr : arrays[i].data(), false)) << "array " << i;
    std::vector<float> l, r;
    host.control(kAzimuth) = 60.0f;
    host.control(kTracking) = 1.0f;  // no worker: nothing starts, nothing crashes
    for (int k = 0; k < 40; ++k) host.run(&l, &r);
    EXPECT_GT(ild(l, r), 6.0) << "array " << i;
  }
}

// lv2:enabled off: the input, delayed by the reported latency, on both
// channels (after a fade when switched while playing); back on, the render.
TEST(Lv2Plugin, BypassIsTheInputDelayedByTheLatency) {
  Host host(plugin_library());
  ASSERT_TRUE(host.instantiate());
  host.control(kAzimuth) = 60.0f;
  host.control(kEnabled) = 0.0f;
  host.activate();  // bypassed from the first block after activate: no fade
  std::vector<float> in, l, r;
  for (int i = 0; i < 8; ++i) host.run(&l, &r, &in);
  const std::size_t latency = static_cast<std::size_t>(host.control(kLatency));
  ASSERT_EQ(latency, 128u);
  for (std::size_t i = latency; i < in.size(); ++i) {
    ASSERT_EQ(l[i], in[i - latency]) << i;
    ASSERT_EQ(r[i], in[i - latency]) << i;
  }
  // Switched on while playing: it fades to the render (ILD of a source on the left).
  host.control(kEnabled) = 1.0f;
  l.clear();
  r.clear();
  for (int i = 0; i < 8; ++i) host.run();  // the 1024-frame fade and more
  for (int i = 0; i < 40; ++i) host.run(&l, &r);
  EXPECT_GT(ild(l, r), 6.0);
  // And off again: the fade ends on the dry input.
  host.control(kEnabled) = 0.0f;
  in.clear();
  l.clear();
  r.clear();
  for (int i = 0; i < 8; ++i) host.run(&l, &r, &in);
  for (std::size_t i = 1024 + latency; i < in.size(); ++i) ASSERT_EQ(l[i], r[i]) << i;
}

// IEM SceneRotator's invert switches and rotation order, on the head the
// panner turns: invert yaw makes the yaw offset's left a right.
TEST(Lv2Plugin, InvertSwitchesAndRotationOrderTurnTheHead) {
  Host host(plugin_library());
  ASSERT_TRUE(host.instantiate());
  host.control(kYawOffset) = 40.0f;
  host.run();
  EXPECT_NEAR(host.control(kHeadYaw), 40.0f, 1e-3);
  host.control(kInvertYaw) = 1.0f;
  host.run();
  EXPECT_NEAR(host.control(kHeadYaw), -40.0f, 1e-3);
  host.control(kInvertYaw) = 0.0f;
  host.control(kPitchOffset) = 20.0f;
  host.control(kInvertPitch) = 1.0f;
  host.run();
  EXPECT_NEAR(host.control(kHeadPitch), -20.0f, 1e-3);
  host.control(kInvertPitch) = 0.0f;
  host.control(kPitchOffset) = 0.0f;
  host.control(kRollOffset) = 10.0f;
  host.control(kInvertRoll) = 1.0f;
  host.run();
  EXPECT_NEAR(host.control(kHeadRoll), -10.0f, 1e-3);
  // The other order changes a combined turn, not a single one.
  host.control(kInvertRoll) = 0.0f;
  host.control(kPitchOffset) = 40.0f;
  host.control(kRollOffset) = 40.0f;
  host.run();
  const std::array<float, 3> ypr{host.control(kHeadYaw), host.control(kHeadPitch), host.control(kHeadRoll)};
  host.control(kRotationOrder) = 1.0f;
  host.run();
  const float moved = std::max({std::abs(host.control(kHeadYaw) - ypr[0]), std::abs(host.control(kHeadPitch) - ypr[1]),
                                std::abs(host.control(kHeadRoll) - ypr[2])});
  EXPECT_GT(moved, 5.0f) << "roll-pitch-yaw composed like yaw-pitch-roll";
  host.control(kPitchOffset) = host.control(kRollOffset) = 0.0f;
  host.run();
  EXPECT_NEAR(host.control(kHeadYaw), 40.0f, 1e-3) << "a yaw alone is the same in either order";
}

namespace {

/// A UDP socket on a free port of 127.0.0.1.
struct Udp {
  int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  std::uint16_t port = 0;
  Udp() {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t n = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
    port = ntohs(a.sin_port);
  }
  ~Udp() { ::close(fd); }
  void send_to(std::uint16_t to, const std::vector<std::uint8_t>& bytes) const {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(to);
    ::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
  }
  /// The next datagram within `ms`, or empty.
  std::vector<std::uint8_t> receive(int ms) const {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, ms) <= 0) return {};
    std::vector<std::uint8_t> b(2048);
    const ssize_t n = ::recv(fd, b.data(), b.size(), 0);
    b.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
    return b;
  }
};

/// "/earshot/ypr" with three float32 arguments.
std::vector<std::uint8_t> earshot_ypr(float yaw) {
  std::vector<std::uint8_t> b{'/', 'e', 'a', 'r', 's', 'h', 'o', 't', '/', 'y', 'p', 'r', 0, 0, 0, 0, ',', 'f', 'f', 'f', 0, 0, 0, 0};
  for (float v : {yaw, 0.0f, 0.0f}) {
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    for (int k = 3; k >= 0; --k) b.push_back(static_cast<std::uint8_t>(u >> (8 * k)));
  }
  return b;
}

}  // namespace

// The OSC port as a visible integer port: tracker_source osc listens where
// osc_port says, and the send parameter passes the head on (Earshot's OSC
// format), both on 127.0.0.1.
TEST(Lv2Plugin, OscPortPortAndSendParameter) {
  Udp probe;  // a free port for the tracker: taken, then given up
  const std::uint16_t port = probe.port;
  ::close(probe.fd);
  probe.fd = -1;
  Udp sender, receiver;
  Host host(plugin_library());
  ASSERT_TRUE(host.instantiate());
  host.patch_set("urn:earshot:lv2:panner#send", "osc:127.0.0.1:" + std::to_string(receiver.port), LV2_ATOM__String);
  host.control(kTracking) = 1.0f;
  host.control(kTrackerSource) = 3.0f;  // osc
  host.control(kOscPort) = static_cast<float>(port);
  host.run();
  host.work();
  host.deliver();
  bool turned = false;
  for (int i = 0; i < 300 && !turned; ++i) {  // bounded: at most ~3 s
    sender.send_to(port, earshot_ypr(30.0f));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    host.run();
    turned = std::abs(host.control(kHeadYaw) - 30.0f) < 0.01f;
  }
  EXPECT_TRUE(turned) << "the head never turned: the osc source is not on osc_port " << port;
  const auto got = receiver.receive(3000);
  ASSERT_FALSE(got.empty()) << "nothing sent to the send parameter's port";
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(got.data())), "/earshot/pose/quat");
  EXPECT_EQ(host.save()["urn:earshot:lv2:panner#send"],
            std::make_pair("osc:127.0.0.1:" + std::to_string(receiver.port), std::string(LV2_ATOM__String)));
  host.control(kTracking) = 0.0f;
  host.run();
  host.work();
}
