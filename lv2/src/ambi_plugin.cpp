// The LV2 Ambisonic decoders of earshot.lv2: one plugin per order,
// `urn:earshot:lv2:ambi-binaural-o1` ... `-o5`, each (N+1)^2 audio inputs
// (ambiX: ACN, SN3D) to two binaural outputs for a head-tracked listener
// (AmbiDecoder, ambi_decoder.hpp), the head from the same tracker specs and
// the same process-wide shared trackers as the panner (shared_tracker.hpp),
// with yaw/pitch/roll offsets, recenter and the latency reported.
//
// Threads, as LV2 defines them (and as the panner, lv2_plugin.cpp):
//   - instantiate / restore / cleanup: the decoder's filters come from the
//     process's caches (designed once per set, rate and order, kept on
//     disk: ambisonics/decoder_cache.hpp); the HRTF set is MIT KEMAR.
//   - run: ports, the control sequence (patch:Set of the tracker spec,
//     patch:Get), the tracker's PoseSlot, the decoder. Never allocates,
//     locks, logs or does I/O.
//   - work: starts and drops tracker leases; work_response adopts them.
// Everything lives in namespace earshot::lv2::ambi, apart from the panner's
// names (the two files may share one unity translation unit).
#include <lv2/atom/forge.h>
#include <lv2/atom/util.h>
#include <lv2/core/lv2.h>
#include <lv2/log/log.h>
#include <lv2/log/logger.h>
#include <lv2/patch/patch.h>
#include <lv2/state/state.h>
#include <lv2/urid/urid.h>
#include <lv2/worker/worker.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "ambi_decoder.hpp"
#include "ambi_plugin.hpp"
#include "earshot/audio/ambisonics/decoder_cache.hpp"
#include "earshot/audio/ambisonics/spherical_harmonics.hpp"
#include "earshot/audio/hrtf_cache.hpp"
#include "earshot/head/head_reader.hpp"
#include "earshot/hrtf/hrtf_set.hpp"
#include "handoff.hpp"
#include "patch_reader.hpp"
#include "plugin_glue.hpp"
#include "shared_tracker.hpp"

namespace earshot::lv2::ambi {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// The tracker_source port's choices (the panner's).
constexpr std::array<const char*, 4> kSources{"wiimote", "sim", "opentrack", "osc"};
constexpr std::size_t kMaxText = 4096;
constexpr std::size_t kSlots = 16;

enum class Job : std::uint32_t { start_tracker, drop_tracker };
struct Message {
  Job job;
  std::int32_t slot;
  char text[kMaxText];
};
struct Reply {
  Job job;
  std::int32_t slot;
};
struct LeaseHolder {
  std::shared_ptr<TrackerLease> lease;
};

struct Uris {
  LV2_URID atom_string = 0, atom_urid = 0, atom_resource = 0, atom_object = 0;
  LV2_URID patch_set = 0, patch_get = 0, patch_property = 0, patch_value = 0, tracker = 0;
  explicit Uris(const LV2_URID_Map* m) {
    if (!m) return;
    auto map = [m](const char* uri) { return m->map(m->handle, uri); };
    atom_string = map(LV2_ATOM__String);
    atom_urid = map(LV2_ATOM__URID);
    atom_resource = map(LV2_ATOM__Resource);
    atom_object = map(LV2_ATOM__Object);
    patch_set = map(LV2_PATCH__Set);
    patch_get = map(LV2_PATCH__Get);
    patch_property = map(LV2_PATCH__property);
    patch_value = map(LV2_PATCH__value);
    tracker = map(kTrackerParameter);
  }
};

std::string reserved(std::size_t n) {
  std::string s;
  s.reserve(n);
  return s;
}

std::shared_ptr<const ambisonics::DecoderFilters> default_filters(int order, double rate) {
  const audio::PreparedHrtf hrtf = audio::HrtfCache::shared().get(hrtf::HrtfSet::kDefaultPath, rate, AmbiDecoder::kBlock);
  return ambisonics::DecoderCache::shared().get(hrtf::HrtfSet::kDefaultPath, *hrtf.set, std::nullopt, order);
}

class Plugin {
 public:
  Plugin(double rate, const LV2_Feature* const* features, int order)
      : ports_(port_count(order), nullptr), decoder_(default_filters(order, rate), rate), rate_(rate) {
    const LV2_URID_Map* map = nullptr;
    for (int i = 0; features && features[i]; ++i) {
      const std::string_view uri = features[i]->URI ? features[i]->URI : "";
      if (uri == LV2_URID__map) map = static_cast<const LV2_URID_Map*>(features[i]->data);
      if (uri == LV2_WORKER__schedule) schedule_ = static_cast<LV2_Worker_Schedule*>(features[i]->data);
      if (uri == LV2_LOG__log) log_ = static_cast<LV2_Log_Log*>(features[i]->data);
    }
    map_ = map;
    uris_ = Uris(map);
    lv2_log_logger_init(&logger_, const_cast<LV2_URID_Map*>(map), log_);
    if (map) lv2_atom_forge_init(&forge_, const_cast<LV2_URID_Map*>(map));
  }

  [[nodiscard]] std::size_t channels() const { return decoder_.channels(); }
  [[nodiscard]] std::uint32_t port(Port p) const { return static_cast<std::uint32_t>(channels()) + p; }

  void connect(std::uint32_t index, void* data) {
    if (index < ports_.size()) ports_[index] = data;
  }
  void activate() { decoder_.reset(); }

  void run(std::uint32_t frames) {
    read_control_events();
    request_tracker();
    HeadPose tracked;
    if (holder_) {
      const bool recenter = control(kRecenter) > 0.5f;
      if (recenter && !recenter_was_) holder_->lease->head->recenter();
      recenter_was_ = recenter;
      // Heard after the host's block and the decoder's own latency.
      const double lead = (static_cast<double>(frames) + static_cast<double>(decoder_.latency())) / rate_;
      tracked = head_reader_.read(holder_->lease->slot, {.predict = true, .lead_s = lead});
    } else {
      head_reader_.reset();
    }
    // The offsets are the listener's own orientation; the tracked head turns on top of it.
    HeadPose listener;
    listener.orientation =
        quat_from_ypr(control(kYawOffset) * kDeg, control(kPitchOffset) * kDeg, control(kRollOffset) * kDeg);
    const HeadPose heard = head::compose(listener, tracked);
    decoder_.set_orientation(heard.orientation);

    auto* left = static_cast<float*>(ports_[port(kOutLeft)]);
    auto* right = static_cast<float*>(ports_[port(kOutRight)]);
    if (left && right)
      decoder_.process(reinterpret_cast<const float* const*>(ports_.data()), left, right, frames);

    const YawPitchRoll head = ypr_from_quat(heard.orientation);
    set_output(kLatency, static_cast<float>(decoder_.latency()));
    set_output(kHeadYaw, static_cast<float>(head.yaw / kDeg));
    set_output(kHeadPitch, static_cast<float>(head.pitch / kDeg));
    set_output(kHeadRoll, static_cast<float>(head.roll / kDeg));
    write_notifications();
  }

  LV2_Worker_Status work(LV2_Worker_Respond_Function respond, LV2_Worker_Respond_Handle handle, std::uint32_t size,
                         const void* data) {
    if (size < offsetof(Message, text)) return LV2_WORKER_ERR_UNKNOWN;
    Message m{};
    std::memcpy(&m, data, std::min<std::size_t>(size, sizeof m));
    m.text[kMaxText - 1] = '\0';
    if (m.job == Job::drop_tracker) {
      (void)dead_holders_.take(m.slot);  // freed here, off the audio thread
      return LV2_WORKER_SUCCESS;
    }
    if (m.job != Job::start_tracker) return LV2_WORKER_ERR_UNKNOWN;
    Reply r{Job::start_tracker, -1};
    try {
      auto holder = std::make_unique<LeaseHolder>();
      holder->lease = SharedTrackers::process().acquire(m.text);
      r.slot = born_holders_.put(holder);
      if (r.slot < 0) return LV2_WORKER_ERR_NO_SPACE;
    } catch (const std::exception& e) {
      lv2_log_error(&logger_, "earshot.lv2: cannot start tracker '%s': %s\n", m.text, e.what());
      return LV2_WORKER_ERR_UNKNOWN;
    }
    if (respond(handle, sizeof r, &r) != LV2_WORKER_SUCCESS) (void)born_holders_.take(r.slot);
    return LV2_WORKER_SUCCESS;
  }

  LV2_Worker_Status work_response(std::uint32_t size, const void* data) {
    if (size != sizeof(Reply)) return LV2_WORKER_ERR_UNKNOWN;
    Reply r;
    std::memcpy(&r, data, sizeof r);
    if (r.job != Job::start_tracker) return LV2_WORKER_ERR_UNKNOWN;
    std::unique_ptr<LeaseHolder> next = born_holders_.take(r.slot);
    if (!next) return LV2_WORKER_ERR_UNKNOWN;
    if (tracker_requested_ == next->lease->head->spec()) std::swap(holder_, next);
    if (next) hand_to_worker(std::move(next));
    return LV2_WORKER_SUCCESS;
  }

  LV2_State_Status save(LV2_State_Store_Function store, LV2_State_Handle handle, const LV2_Feature* const*) {
    if (!map_) return LV2_STATE_ERR_NO_FEATURE;
    store(handle, uris_.tracker, tracker_spec_.c_str(), tracker_spec_.size() + 1, uris_.atom_string,
          LV2_STATE_IS_POD | LV2_STATE_IS_PORTABLE);
    return LV2_STATE_SUCCESS;
  }

  LV2_State_Status restore(LV2_State_Retrieve_Function retrieve, LV2_State_Handle handle, const LV2_Feature* const*) {
    if (!map_) return LV2_STATE_ERR_NO_FEATURE;
    std::size_t size = 0;
    std::uint32_t type = 0, flags = 0;
    if (const void* v = retrieve(handle, uris_.tracker, &size, &type, &flags); v && type == uris_.atom_string) {
      const std::string_view s(static_cast<const char*>(v), strnlen(static_cast<const char*>(v), size));
      if (s.size() < tracker_spec_.capacity()) tracker_spec_.assign(s);
    }
    return LV2_STATE_SUCCESS;
  }

 private:
  static std::size_t port_count(int order) {
    return ambisonics::channel_count(order) + static_cast<std::size_t>(kPortsAfterInputs);
  }
  [[nodiscard]] float control(Port p) const {
    const auto* v = static_cast<const float*>(ports_[port(p)]);
    return v && std::isfinite(*v) ? *v : 0.0f;
  }
  void set_output(Port p, float value) {
    if (auto* v = static_cast<float*>(ports_[port(p)])) *v = value;
  }

  void hand_to_worker(std::unique_ptr<LeaseHolder> old) {
    const int slot = dead_holders_.put(old);
    if (slot < 0) {
      parked_ = std::move(old);  // every slot taken: parked (a second in a row frees the older here)
      return;
    }
    Message m;
    m.job = Job::drop_tracker;
    m.slot = slot;
    m.text[0] = '\0';
    if (schedule_) (void)schedule_->schedule_work(schedule_->handle, offsetof(Message, text) + 1, &m);
  }

  [[nodiscard]] std::string_view wanted_tracker() const {
    if (control(kTracking) <= 0.5f) return {};
    if (!tracker_spec_.empty()) return tracker_spec_;
    const int i = static_cast<int>(std::lround(control(kTrackerSource)));
    return kSources[static_cast<std::size_t>(std::clamp(i, 0, 3))];
  }

  /// Starts or drops the tracker when the ports changed what they ask for
  /// (tracker_requested_ has its capacity reserved: no allocation).
  void request_tracker() {
    const std::string_view want = wanted_tracker();
    if (want == std::string_view(tracker_requested_) || want.size() >= tracker_requested_.capacity()) return;
    if (holder_) hand_to_worker(std::move(holder_));
    if (!want.empty()) {
      if (!schedule_) return;
      Message m;
      m.job = Job::start_tracker;
      m.slot = -1;
      std::memcpy(m.text, want.data(), want.size());
      m.text[want.size()] = '\0';
      if (schedule_->schedule_work(schedule_->handle, static_cast<std::uint32_t>(offsetof(Message, text) + want.size() + 1),
                                   &m) != LV2_WORKER_SUCCESS)
        return;  // retried next run()
    }
    tracker_requested_.assign(want);
  }

  /// patch:Set of the tracker spec, patch:Get. The host's bytes are checked
  /// before they are read: every event, property and value must lie inside
  /// the sequence (patch_reader.hpp).
  void read_control_events() {
    if (!map_) return;
    read_patch_messages(
        static_cast<const LV2_Atom_Sequence*>(ports_[port(kControl)]), uris_, [this] { announce_ = true; },
        [this](LV2_URID key, const LV2_Atom* value, std::string_view s) {
          if (key != uris_.tracker || value->type != uris_.atom_string) return;
          if (s.size() < tracker_spec_.capacity()) tracker_spec_.assign(s);  // capacity reserved: no allocation
          announce_ = true;
        });
  }

  void write_notifications() {
    auto* seq = static_cast<LV2_Atom_Sequence*>(ports_[port(kNotify)]);
    if (!seq || !map_) return;
    lv2_atom_forge_set_buffer(&forge_, reinterpret_cast<std::uint8_t*>(seq), seq->atom.size);
    LV2_Atom_Forge_Frame seq_frame;
    lv2_atom_forge_sequence_head(&forge_, &seq_frame, 0);
    if (announce_) {
      LV2_Atom_Forge_Frame frame;
      lv2_atom_forge_frame_time(&forge_, 0);
      lv2_atom_forge_object(&forge_, &frame, 0, uris_.patch_set);
      lv2_atom_forge_key(&forge_, uris_.patch_property);
      lv2_atom_forge_urid(&forge_, uris_.tracker);
      lv2_atom_forge_key(&forge_, uris_.patch_value);
      lv2_atom_forge_string(&forge_, tracker_spec_.c_str(), static_cast<std::uint32_t>(tracker_spec_.size()));
      lv2_atom_forge_pop(&forge_, &frame);
      announce_ = false;
    }
    lv2_atom_forge_pop(&forge_, &seq_frame);
  }

  std::vector<void*> ports_;
  AmbiDecoder decoder_;
  double rate_;
  const LV2_URID_Map* map_ = nullptr;
  Uris uris_{nullptr};
  LV2_Worker_Schedule* schedule_ = nullptr;
  LV2_Log_Log* log_ = nullptr;
  LV2_Log_Logger logger_{};
  LV2_Atom_Forge forge_{};
  std::unique_ptr<LeaseHolder> holder_, parked_;
  Handoff<LeaseHolder, kSlots> born_holders_, dead_holders_;
  std::string tracker_spec_ = reserved(256);       // from state or patch:Set; "" = the source port
  std::string tracker_requested_ = reserved(256);  // what run() last asked the worker for
  head::HeadReader head_reader_;
  bool recenter_was_ = false, announce_ = false;
};

using Glue = PluginGlue<Plugin>;

template <int Order>
LV2_Handle instantiate(const LV2_Descriptor*, double rate, const char*, const LV2_Feature* const* features) {
  static const std::string name = "earshot.lv2 (Ambisonic order " + std::to_string(Order) + ")";
  return Glue::make(name.c_str(), rate, features, Order);
}

#define EARSHOT_AMBI_DESCRIPTOR(n) Glue::descriptor(EARSHOT_LV2_AMBI_URI_PREFIX #n, instantiate<n>)
const std::array<LV2_Descriptor, kOrders> kDescriptors{EARSHOT_AMBI_DESCRIPTOR(1), EARSHOT_AMBI_DESCRIPTOR(2),
                                                       EARSHOT_AMBI_DESCRIPTOR(3), EARSHOT_AMBI_DESCRIPTOR(4),
                                                       EARSHOT_AMBI_DESCRIPTOR(5)};
#undef EARSHOT_AMBI_DESCRIPTOR

}  // namespace

const LV2_Descriptor* descriptor(std::uint32_t i) { return i < kDescriptors.size() ? &kDescriptors[i] : nullptr; }

}  // namespace earshot::lv2::ambi
