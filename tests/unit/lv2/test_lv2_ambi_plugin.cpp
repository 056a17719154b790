// The LV2 Ambisonic decoders in the built binary (earshot.lv2/earshot.so),
// driven through their descriptors by a small host of our own: the ports
// the turtle says, a plane wave from the left heard on the left and turned
// by the yaw offset, the latency reported, run() neither allocating nor
// locking while it asks for a tracker and adopts it, the tracked head
// turning the field, the tracker spec saved and restored.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <lv2/atom/atom.h>
#include <lv2/core/lv2.h>
#include <lv2/state/state.h>
#include <lv2/urid/urid.h>
#include <lv2/worker/worker.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "../audio/alloc_counter.hpp"
#include "binaural_cues.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double kAmbiRate = 48000.0;
constexpr std::uint32_t kAmbiFrames = 256;
// Ports after the (N+1)^2 inputs (lv2/src/ambi_plugin.hpp).
enum AmbiPort : std::uint32_t { kLeft = 0, kRight, kCtl, kNote, kTrack, kSource, kCentre, kYaw, kPitch, kRoll,
                                kLat, kHeadYawOut, kHeadPitchOut, kHeadRollOut, kAfterInputs };

class AmbiHost {
 public:
  explicit AmbiHost(int order) : channels_(static_cast<std::uint32_t>((order + 1) * (order + 1))) {
    dl_ = dlopen((fs::path(EARSHOT_LV2_BUNDLE) / "earshot.so").c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!dl_) throw std::runtime_error(dlerror());
    auto fn = reinterpret_cast<LV2_Descriptor_Function>(dlsym(dl_, "lv2_descriptor"));
    desc_ = fn ? fn(static_cast<std::uint32_t>(order)) : nullptr;
    if (!desc_ || std::string(desc_->URI) != "urn:earshot:lv2:ambi-binaural-o" + std::to_string(order))
      throw std::runtime_error("no Ambisonic descriptor of order " + std::to_string(order));
    worker_ = static_cast<const LV2_Worker_Interface*>(desc_->extension_data(LV2_WORKER__interface));
    state_ = static_cast<const LV2_State_Interface*>(desc_->extension_data(LV2_STATE__interface));
    uris_.reserve(256);
    inputs_.assign(channels_, std::vector<float>(kAmbiFrames, 0.0f));
    controls_.fill(0.0f);
  }
  ~AmbiHost() {
    if (handle_) desc_->cleanup(handle_);
    if (dl_) dlclose(dl_);
  }
  AmbiHost(const AmbiHost&) = delete;
  AmbiHost& operator=(const AmbiHost&) = delete;

  bool instantiate() {
    schedule_ = {this, [](LV2_Worker_Schedule_Handle h, std::uint32_t size, const void* data) {
                   auto* self = static_cast<AmbiHost*>(h);
                   if (self->jobs_n_ == self->jobs_.size() || size > self->jobs_[0].size()) return LV2_WORKER_ERR_NO_SPACE;
                   std::memcpy(self->jobs_[self->jobs_n_].data(), data, size);
                   self->job_sizes_[self->jobs_n_++] = size;
                   return LV2_WORKER_SUCCESS;
                 }};
    map_feature_ = {LV2_URID__map, &map_};
    schedule_feature_ = {LV2_WORKER__schedule, &schedule_};
    features_ = {&map_feature_, &schedule_feature_, nullptr};
    handle_ = desc_->instantiate(desc_, kAmbiRate, "", features_.data());
    if (!handle_) return false;
    for (std::uint32_t c = 0; c < channels_; ++c) desc_->connect_port(handle_, c, inputs_[c].data());
    desc_->connect_port(handle_, channels_ + kLeft, left_.data());
    desc_->connect_port(handle_, channels_ + kRight, right_.data());
    desc_->connect_port(handle_, channels_ + kCtl, control_.data());
    desc_->connect_port(handle_, channels_ + kNote, notify_.data());
    for (std::uint32_t p = kTrack; p < kAfterInputs; ++p) desc_->connect_port(handle_, channels_ + p, &controls_[p]);
    auto* seq = reinterpret_cast<LV2_Atom_Sequence*>(control_.data());
    seq->atom.type = map(LV2_ATOM__Sequence);
    seq->atom.size = sizeof(LV2_Atom_Sequence_Body);
    desc_->activate(handle_);
    return true;
  }

  float& control(AmbiPort p) { return controls_[p]; }

  /// One run() of a plane wave of noise from `az_deg` (horizontal, first order's channels).
  void run(double az_deg, std::vector<float>* l = nullptr, std::vector<float>* r = nullptr) {
    const double az = az_deg * 3.14159265358979323846 / 180.0;
    for (std::uint32_t i = 0; i < kAmbiFrames; ++i) {
      const float s = noise_(rng_);
      inputs_[0][i] = s;
      inputs_[1][i] = static_cast<float>(std::sin(az)) * s;
      inputs_[3][i] = static_cast<float>(std::cos(az)) * s;
    }
    auto* n = reinterpret_cast<LV2_Atom_Sequence*>(notify_.data());
    n->atom.size = static_cast<std::uint32_t>(notify_.size() * 8 - sizeof(LV2_Atom));
    desc_->run(handle_, kAmbiFrames);
    if (l) l->insert(l->end(), left_.begin(), left_.end());
    if (r) r->insert(r->end(), right_.begin(), right_.end());
  }

  /// The worker thread's turn, then the answers to the plugin.
  void work_and_deliver() {
    const std::size_t n = jobs_n_;
    jobs_n_ = 0;
    std::vector<std::vector<std::uint8_t>> answers;
    for (std::size_t i = 0; i < n; ++i)
      worker_->work(
          handle_,
          [](LV2_Worker_Respond_Handle h, std::uint32_t size, const void* data) {
            auto* a = static_cast<std::vector<std::vector<std::uint8_t>>*>(h);
            a->emplace_back(static_cast<const std::uint8_t*>(data), static_cast<const std::uint8_t*>(data) + size);
            return LV2_WORKER_SUCCESS;
          },
          &answers, job_sizes_[i], jobs_[i].data());
    for (const auto& a : answers) worker_->work_response(handle_, static_cast<std::uint32_t>(a.size()), a.data());
  }
  [[nodiscard]] std::size_t jobs() const { return jobs_n_; }

  std::map<std::string, std::string> save() {
    std::map<std::string, std::string> out;
    struct Ctx {
      AmbiHost* self;
      std::map<std::string, std::string>* out;
    } ctx{this, &out};
    state_->save(
        handle_,
        [](LV2_State_Handle h, std::uint32_t key, const void* value, std::size_t size, std::uint32_t, std::uint32_t) {
          auto* c = static_cast<Ctx*>(h);
          (*c->out)[c->self->uris_[key - 1]] = std::string(static_cast<const char*>(value), size - 1);
          return LV2_STATE_SUCCESS;
        },
        &ctx, 0, features_.data());
    return out;
  }
  LV2_State_Status restore(const std::string& key, const std::string& value) {
    restore_key_ = map(key.c_str());
    restore_value_ = value;
    return state_->restore(
        handle_,
        [](LV2_State_Handle h, std::uint32_t k, std::size_t* size, std::uint32_t* type, std::uint32_t* flags) -> const void* {
          auto* self = static_cast<AmbiHost*>(h);
          if (k != self->restore_key_) return nullptr;
          *size = self->restore_value_.size() + 1;
          *type = self->map(LV2_ATOM__String);
          *flags = LV2_STATE_IS_POD;
          return self->restore_value_.c_str();
        },
        this, 0, features_.data());
  }

  LV2_URID map(const char* uri) {
    for (std::size_t i = 0; i < uris_.size(); ++i)
      if (uris_[i] == uri) return static_cast<LV2_URID>(i + 1);
    uris_.emplace_back(uri);
    return static_cast<LV2_URID>(uris_.size());
  }

 private:
  std::uint32_t channels_;
  void* dl_ = nullptr;
  const LV2_Descriptor* desc_ = nullptr;
  const LV2_Worker_Interface* worker_ = nullptr;
  const LV2_State_Interface* state_ = nullptr;
  LV2_Handle handle_ = nullptr;
  std::vector<std::string> uris_;
  LV2_URID_Map map_{this, [](LV2_URID_Map_Handle h, const char* uri) { return static_cast<AmbiHost*>(h)->map(uri); }};
  LV2_Worker_Schedule schedule_{};
  LV2_Feature map_feature_{}, schedule_feature_{};
  std::array<const LV2_Feature*, 3> features_{};
  std::array<std::array<std::uint8_t, 8192>, 8> jobs_{};
  std::array<std::uint32_t, 8> job_sizes_{};
  std::size_t jobs_n_ = 0;
  std::vector<std::vector<float>> inputs_;
  std::array<float, kAmbiFrames> left_{}, right_{};
  std::array<float, kAfterInputs> controls_{};
  std::array<std::uint64_t, 512> control_{}, notify_{};
  std::mt19937 rng_{9};
  std::normal_distribution<float> noise_{0.0f, 0.1f};
  LV2_URID restore_key_ = 0;
  std::string restore_value_;
};

double ambi_ild(const std::vector<float>& l, const std::vector<float>& r) { return earshot::analysis::ild_db(l, r); }

}  // namespace

TEST(Lv2AmbiPlugin, AWaveFromTheLeftIsOnTheLeftUntilTheYawOffsetFacesIt) {
  for (int order : {1, 3}) {
    AmbiHost host(order);
    ASSERT_TRUE(host.instantiate());
    std::vector<float> l, r;
    for (int i = 0; i < 40; ++i) host.run(90.0, i >= 8 ? &l : nullptr, i >= 8 ? &r : nullptr);
    EXPECT_GT(ambi_ild(l, r), 6.0) << "order " << order;
    EXPECT_EQ(host.control(kLat), 128.0f);
    host.control(kYaw) = 90.0f;  // the listener turned left, to the wave
    l.clear();
    r.clear();
    for (int i = 0; i < 40; ++i) host.run(90.0, i >= 8 ? &l : nullptr, i >= 8 ? &r : nullptr);
    EXPECT_NEAR(ambi_ild(l, r), 0.0, 1.0) << "order " << order;
    EXPECT_NEAR(host.control(kHeadYawOut), 90.0f, 1e-3);
  }
}

TEST(Lv2AmbiPlugin, RunNeverAllocatesOrLocksWhileItStartsAndFollowsATracker) {
  AmbiHost host(3);
  ASSERT_TRUE(host.instantiate());
  for (int i = 0; i < 4; ++i) host.run(0.0);
  {
    earshot::testing::AllocationProbe probe;
    host.control(kTrack) = 1.0f;
    host.control(kSource) = 1.0f;  // sim
    for (int i = 0; i < 8; ++i) {
      host.control(kYaw) = static_cast<float>(i * 5);
      host.run(0.0);
    }
    EXPECT_EQ(probe.count(), 0u);
    EXPECT_EQ(probe.lock_count(), 0u);
  }
  ASSERT_EQ(host.jobs(), 1u);  // the tracker, for the worker
  host.work_and_deliver();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the simulated head's first poses
  {
    earshot::testing::AllocationProbe probe;
    for (int i = 0; i < 32; ++i) host.run(0.0);
    host.control(kCentre) = 1.0f;  // recenter: a flag to the tracker thread
    host.run(0.0);
    host.control(kCentre) = 0.0f;
    host.run(0.0);
    EXPECT_EQ(probe.count(), 0u);
    EXPECT_EQ(probe.lock_count(), 0u);
  }
  host.control(kTrack) = 0.0f;
  host.run(0.0);
  EXPECT_EQ(host.jobs(), 1u);  // the lease back to the worker
  host.work_and_deliver();
}

TEST(Lv2AmbiPlugin, StateKeepsTheTrackerSpec) {
  AmbiHost host(2);
  ASSERT_TRUE(host.instantiate());
  ASSERT_EQ(host.restore("urn:earshot:lv2:ambi-binaural#tracker", "osc:19999"), LV2_STATE_SUCCESS);
  const auto saved = host.save();
  ASSERT_EQ(saved.count("urn:earshot:lv2:ambi-binaural#tracker"), 1u);
  EXPECT_EQ(saved.at("urn:earshot:lv2:ambi-binaural#tracker"), "osc:19999");
}
