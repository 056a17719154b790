// earshot.lv2: the LV2 face of BinauralPanner (binaural_panner.hpp) and of
// the process's shared head trackers (shared_tracker.hpp).
//
// Threads, as LV2 defines them:
//   - instantiate / restore / cleanup (instantiation class): may allocate,
//     load the SOFA file, start and join trackers.
//   - run (audio class): reads the ports and the control sequence, reads
//     the tracker's PoseSlot, renders. Never allocates, locks, logs or does
//     I/O (tests/unit/lv2 proves it). Anything slow is a job for the worker.
//   - work (the host's worker thread): loads SOFA sets (through the
//     process's HrtfCache), builds the panner that uses them, starts and
//     drops tracker leases, frees what the audio thread let go of.
//   - work_response (audio class again): adopts what the worker built.
// Objects cross threads through Handoff slots the instance owns (handoff.hpp):
// a worker message carries a slot number, never a pointer; nothing is ever
// freed in run(), and nothing is leaked if the host cleans up with work or
// answers still pending.
#include <lv2/atom/forge.h>
#include <lv2/atom/util.h>
#include <lv2/core/lv2.h>
#include <lv2/log/log.h>
#include <lv2/log/logger.h>
#include <lv2/state/state.h>
#include <lv2/worker/worker.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <numbers>
#include <string>

#include "ambi_plugin.hpp"
#include "binaural_panner.hpp"
#include "bypass.hpp"
#include "head_controls.hpp"
#include "panner_switch.hpp"
#include "earshot/audio/hrtf_cache.hpp"
#include "earshot/audio/room_presets.hpp"
#include "earshot/head/head_reader.hpp"
#include "earshot/hrtf/hrtf_set.hpp"
#include "features.hpp"
#include "handoff.hpp"
#include "patch_reader.hpp"
#include "plugin_glue.hpp"
#include "shared_tracker.hpp"
#include "uris.hpp"

namespace earshot::lv2 {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// Port indices: the same numbers as lv2:index in lv2/ttl/earshot.ttl.in.
enum Port : std::uint32_t {
  kIn = 0,
  kOutLeft,
  kOutRight,
  kControl,  // atom:Sequence of patch:Set / patch:Get (optional)
  kNotify,   // atom:Sequence out (optional)
  kAzimuth,
  kElevation,
  kDistance,
  kGain,
  kDistanceModel,
  kRoom,
  kReverbSend,
  kTracking,
  kTrackerSource,
  kRecenter,
  kYawOffset,
  kPitchOffset,
  kRollOffset,
  kLatency,
  kHeadYaw,
  kHeadPitch,
  kHeadRoll,
  // Appended (minor version 2): earlier sessions keep their port numbers.
  kEnabled,      // lv2:enabled: off bypasses (the input, delayed, on both channels)
  kInvertYaw,    // IEM SceneRotator's switches and rotation order (head_controls.hpp)
  kInvertPitch,
  kInvertRoll,
  kRotationOrder,
  kOscPort,        // the UDP port of tracker_source osc
  kOpentrackPort,  // and of tracker_source opentrack
  kPortCount
};

/// The tracker_source port's choices, in the order of its scale points.
constexpr std::array<const char*, 4> kTrackerSources{"wiimote", "sim", "opentrack", "osc"};

/// Longest tracker spec and send list the parameters hold (longer ones are
/// refused, not cut; the buffers are reserved so run() never allocates).
constexpr std::size_t kMaxSpec = 256;

/// Longest path or spec a message carries (the rest is refused, not cut).
constexpr std::size_t kMaxText = 4096;

enum class Job : std::uint32_t { load_hrtf, start_tracker, drop_tracker, free_panner };

/// A worker message: a job, the Handoff slot of what it hands over, and a text.
struct Message {
  Job job;
  std::int32_t slot;  // free_panner: in dead_panners_; drop_tracker: in dead_holders_
  char text[kMaxText];
};

/// What the audio thread holds of a shared tracker (the shared_ptr itself
/// lives on the heap, so handing it back to the worker frees nothing here).
struct LeaseHolder {
  std::shared_ptr<TrackerLease> lease;
  std::string key;  ///< what was asked for: "SPEC" or "SPEC\nSEND"
};

/// The worker's answer: the slot of a new panner (born_panners_) or tracker
/// lease (born_holders_).
struct Reply {
  Job job;
  std::int32_t slot;
};

/// Slots per kind: more than the jobs a host's worker queue holds at once.
constexpr std::size_t kSlots = 16;

class Plugin {
 public:
  Plugin(double rate, const LV2_Feature* const* features)
      : rate_(rate), panners_(build_panner(hrtf::HrtfSet::kDefaultPath)) {  // throws: instantiate fails, the host says so
    // features.hpp: entries with a NULL URI (lv2file) are skipped.
    const auto* map = static_cast<const LV2_URID_Map*>(feature_data(features, LV2_URID__map));
    schedule_ = static_cast<LV2_Worker_Schedule*>(const_cast<void*>(feature_data(features, LV2_WORKER__schedule)));
    log_ = static_cast<LV2_Log_Log*>(const_cast<void*>(feature_data(features, LV2_LOG__log)));
    if (map && !map->map) map = nullptr;  // a map without its function is no map
    if (schedule_ && !schedule_->schedule_work) schedule_ = nullptr;
    if (log_ && !log_->printf) log_ = nullptr;
    uris_ = Uris(map);
    map_ = map;
    lv2_log_logger_init(&logger_, const_cast<LV2_URID_Map*>(map), log_);
    if (map) lv2_atom_forge_init(&forge_, const_cast<LV2_URID_Map*>(map));
  }

  ~Plugin() = default;  // the panner and the lease holder go with the instance (instantiation class)

  void connect(std::uint32_t port, void* data) {
    if (port < kPortCount) ports_[port] = data;
  }

  void activate() {
    bypass_start_ = true;  // the first run() starts where the enabled port asks, unfaded
    panners_.reset();
    if (auto old = panners_.finished()) hand_to_worker(std::move(old));
  }

  void run(std::uint32_t frames) {
    read_control_events();
    request_tracker();
    // The tracked head as this block will be heard: after the host's block
    // and the panner's own latency (the host's output latency is not told).
    HeadPose tracked;
    if (holder_) {
      const bool recenter = control(kRecenter) > 0.5f;
      if (recenter && !recenter_was_) holder_->lease->head->recenter();
      recenter_was_ = recenter;
      const double lead = (static_cast<double>(frames) + static_cast<double>(panners_.current().latency())) / rate_;
      tracked = head_reader_.read(holder_->lease->slot, {.predict = true, .lead_s = lead});
    } else {
      head_reader_.reset();
    }

    PannerParams p;
    p.azimuth_deg = control(kAzimuth);
    p.elevation_deg = std::clamp(static_cast<double>(control(kElevation)), -90.0, 90.0);
    p.distance_m = std::clamp(static_cast<double>(control(kDistance)), 0.05, 1000.0);
    p.gain_db = std::clamp(static_cast<double>(control(kGain)), -120.0, 24.0);
    const int model = static_cast<int>(std::lround(control(kDistanceModel)));
    p.distance_model = static_cast<audio::DistanceModel>(std::clamp(model, 0, 6));
    p.room = static_cast<int>(std::lround(control(kRoom)));
    p.reverb_send_db = control(kReverbSend);
    const bool enabled = control(kEnabled, 1.0f) > 0.5f;
    if (bypass_start_) bypass_.reset(enabled);  // nothing was heard yet: nothing to fade from
    bypass_start_ = false;
    const HeadControls head_controls{control(kInvertYaw) > 0.5f, control(kInvertPitch) > 0.5f,
                                     control(kInvertRoll) > 0.5f, control(kRotationOrder) > 0.5f ? 1 : 0};
    // The offsets are the listener's own orientation in the room; the
    // tracked head turns on top of it (as the C API's listener and tracker).
    HeadPose listener;
    listener.orientation =
        quat_from_ypr(control(kYawOffset) * kDeg, control(kPitchOffset) * kDeg, control(kRollOffset) * kDeg);
    const HeadPose heard = head::compose(listener, tracked);
    p.head_orientation = heard.orientation;
    p.head_position = heard.position;
    // SceneRotator's invert switches and rotation order, on the head as composed above.
    p.head_orientation = adjust_head(p.head_orientation, head_controls);
    panners_.update(p);

    const auto* in = static_cast<const float*>(ports_[kIn]);
    auto* left = static_cast<float*>(ports_[kOutLeft]);
    auto* right = static_cast<float*>(ports_[kOutRight]);
    if (in && left && right)
      bypass_.process(in, left, right, frames, enabled, [this](const float* i, float* l, float* r, std::uint32_t n) {
        panners_.process(i, l, r, n);
      });
    if (auto old = panners_.finished()) hand_to_worker(std::move(old));  // faded out: the worker frees it

    const YawPitchRoll head = ypr_from_quat(p.head_orientation);
    set_output(kLatency, static_cast<float>(panners_.current().latency()));
    set_output(kHeadYaw, static_cast<float>(head.yaw / kDeg));
    set_output(kHeadPitch, static_cast<float>(head.pitch / kDeg));
    set_output(kHeadRoll, static_cast<float>(head.roll / kDeg));
    write_notifications();
  }

  // ---- worker (the host's worker thread) ----
  LV2_Worker_Status work(LV2_Worker_Respond_Function respond, LV2_Worker_Respond_Handle handle, std::uint32_t size,
                         const void* data) {
    if (size < offsetof(Message, text)) return LV2_WORKER_ERR_UNKNOWN;
    Message m{};
    std::memcpy(&m, data, std::min<std::size_t>(size, sizeof m));
    m.text[kMaxText - 1] = '\0';
    Reply r{m.job, -1};
    switch (m.job) {
      case Job::free_panner: (void)dead_panners_.take(m.slot); return LV2_WORKER_SUCCESS;  // freed here
      case Job::drop_tracker: (void)dead_holders_.take(m.slot); return LV2_WORKER_SUCCESS;
      case Job::load_hrtf:
        try {
          auto panner = build_panner(m.text);
          r.slot = born_panners_.put(panner);
          if (r.slot < 0) return LV2_WORKER_ERR_NO_SPACE;
        } catch (const std::exception& e) {
          lv2_log_error(&logger_, "earshot.lv2: cannot use HRTF set %s: %s (keeping %s)\n", m.text, e.what(),
                        "the current set");
          return LV2_WORKER_ERR_UNKNOWN;
        }
        break;
      case Job::start_tracker:
        try {
          // "SPEC" or "SPEC\nSEND" (wanted_tracker()).
          const std::string_view text(m.text);
          const std::size_t nl = text.find('\n');
          const std::string spec(text.substr(0, nl));
          const std::string send(nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1));
          auto holder = std::make_unique<LeaseHolder>();
          std::string note;
          holder->lease = SharedTrackers::process().acquire(spec, send, &note);
          holder->key = std::string(text);
          if (!note.empty()) lv2_log_warning(&logger_, "earshot.lv2: %s\n", note.c_str());
          r.slot = born_holders_.put(holder);
          if (r.slot < 0) return LV2_WORKER_ERR_NO_SPACE;
        } catch (const std::exception& e) {
          lv2_log_error(&logger_, "earshot.lv2: cannot start tracker '%s': %s\n", m.text, e.what());
          return LV2_WORKER_ERR_UNKNOWN;
        }
        break;
    }
    if (respond(handle, sizeof r, &r) != LV2_WORKER_SUCCESS) {
      // The host cannot take the answer: free it here, on this thread.
      if (r.job == Job::load_hrtf) (void)born_panners_.take(r.slot);
      if (r.job == Job::start_tracker) (void)born_holders_.take(r.slot);
    }
    return LV2_WORKER_SUCCESS;
  }

  // ---- work_response (audio thread) ----
  LV2_Worker_Status work_response(std::uint32_t size, const void* data) {
    if (size != sizeof(Reply)) return LV2_WORKER_ERR_UNKNOWN;
    Reply r;
    std::memcpy(&r, data, sizeof r);
    if (r.job == Job::load_hrtf) {
      std::unique_ptr<BinauralPanner> next = born_panners_.take(r.slot);
      if (!next) return LV2_WORKER_ERR_UNKNOWN;
      // Heard after a warm-up and a crossfade (panner_switch.hpp), never a gap.
      if (auto cut_short = panners_.switch_to(std::move(next))) hand_to_worker(std::move(cut_short));
      announce_sofa_ = true;
    } else if (r.job == Job::start_tracker) {
      std::unique_ptr<LeaseHolder> next = born_holders_.take(r.slot);
      if (!next) return LV2_WORKER_ERR_UNKNOWN;
      if (tracker_requested_ == next->key) {
        std::swap(holder_, next);
      }
      if (next) hand_to_worker(std::move(next));
    }
    return LV2_WORKER_SUCCESS;
  }

  // ---- state (instantiation class) ----
  LV2_State_Status save(LV2_State_Store_Function store, LV2_State_Handle handle, const LV2_Feature* const* features) {
    if (!map_) return LV2_STATE_ERR_NO_FEATURE;
    const auto* map_path = static_cast<const LV2_State_Map_Path*>(feature_data(features, LV2_STATE__mapPath));
    const auto* free_path = static_cast<const LV2_State_Free_Path*>(feature_data(features, LV2_STATE__freePath));
    const std::string& path = panners_.current().hrtf_path();
    char* abstract = map_path && map_path->abstract_path ? map_path->abstract_path(map_path->handle, path.c_str()) : nullptr;
    const char* stored = abstract ? abstract : path.c_str();
    store(handle, uris_.sofa, stored, std::strlen(stored) + 1, uris_.atom_path,
          LV2_STATE_IS_POD | LV2_STATE_IS_PORTABLE);
    if (abstract) {
      if (free_path && free_path->free_path) free_path->free_path(free_path->handle, abstract);
      else std::free(abstract);  // NOLINT: the host allocated it with malloc (LV2 state before freePath)
    }
    store(handle, uris_.tracker, tracker_spec_.c_str(), tracker_spec_.size() + 1, uris_.atom_string,
          LV2_STATE_IS_POD | LV2_STATE_IS_PORTABLE);
    store(handle, uris_.send, send_spec_.c_str(), send_spec_.size() + 1, uris_.atom_string,
          LV2_STATE_IS_POD | LV2_STATE_IS_PORTABLE);
    return LV2_STATE_SUCCESS;
  }

  LV2_State_Status restore(LV2_State_Retrieve_Function retrieve, LV2_State_Handle handle,
                           const LV2_Feature* const* features) {
    if (!map_) return LV2_STATE_ERR_NO_FEATURE;
    const auto* map_path = static_cast<const LV2_State_Map_Path*>(feature_data(features, LV2_STATE__mapPath));
    std::size_t size = 0;
    std::uint32_t type = 0, flags = 0;
    // Restored strings keep the reserved capacity (reserved() below): run()
    // never allocates for them; one too long for it is refused.
    if (const void* v = retrieve(handle, uris_.tracker, &size, &type, &flags); v && type == uris_.atom_string) {
      const std::size_t n = strnlen(static_cast<const char*>(v), size);
      if (n < kMaxSpec) tracker_spec_.assign(static_cast<const char*>(v), n);
    }
    if (const void* v = retrieve(handle, uris_.send, &size, &type, &flags); v && type == uris_.atom_string) {
      const std::string_view sv(static_cast<const char*>(v), strnlen(static_cast<const char*>(v), size));
      if (sv.size() < kMaxSpec && sv.find('\n') == std::string_view::npos) send_spec_.assign(sv);
    }
    if (const void* v = retrieve(handle, uris_.sofa, &size, &type, &flags); v && type == uris_.atom_path) {
      std::string path(static_cast<const char*>(v), strnlen(static_cast<const char*>(v), size));
      if (map_path && map_path->absolute_path) {
        if (char* absolute = map_path->absolute_path(map_path->handle, path.c_str())) {
          path = absolute;
          std::free(absolute);  // NOLINT: allocated by the host with malloc
        }
      }
      if (path != panners_.current().hrtf_path()) {
        try {
          // Not concurrent with run() (LV2's instantiation class): switch at once.
          // The old panners are freed here, at the end of this scope.
          auto cut_short = panners_.switch_to(build_panner(path));
          panners_.reset();  // no crossfade from a state the session never heard
          auto old = panners_.finished();
        } catch (const std::exception& e) {
          lv2_log_error(&logger_, "earshot.lv2: restoring HRTF set %s: %s (keeping %s)\n", path.c_str(), e.what(),
                        panners_.current().hrtf_path().c_str());
          return LV2_STATE_ERR_UNKNOWN;
        }
      }
    }
    return LV2_STATE_SUCCESS;
  }

 private:
  [[nodiscard]] std::unique_ptr<BinauralPanner> build_panner(const std::string& path) const {
    const audio::PreparedHrtf hrtf = audio::HrtfCache::shared().get(path, rate_, BinauralPanner::kBlock);
    return std::make_unique<BinauralPanner>(hrtf, rate_, path);
  }

  /// A control port's value; `fallback` when the host left it unconnected
  /// (connectionOptional is not declared, but hosts such as lv2file with
  /// an older turtle may still leave new ports out) or it is not finite.
  [[nodiscard]] float control(Port p, float fallback = 0.0f) const {
    const auto* v = static_cast<const float*>(ports_[p]);
    return v && std::isfinite(*v) ? *v : fallback;
  }
  void set_output(Port p, float value) {
    if (auto* v = static_cast<float*>(ports_[p])) *v = value;
  }

  /// Gives `old` to the worker, which frees it off the audio thread. It
  /// waits in a slot of the instance until then (freed at cleanup if the
  /// worker never gets to it). With every slot taken it is parked (one of
  /// each kind; a second in a row frees the older one here, the only way out).
  void hand_to_worker(std::unique_ptr<BinauralPanner> old) {
    const int slot = dead_panners_.put(old);
    if (slot < 0) parked_panner_ = std::move(old);
    else send_slot(Job::free_panner, slot);
  }
  void hand_to_worker(std::unique_ptr<LeaseHolder> old) {
    const int slot = dead_holders_.put(old);
    if (slot < 0) parked_holder_ = std::move(old);
    else send_slot(Job::drop_tracker, slot);
  }
  void send_slot(Job job, int slot) {
    Message m;
    m.job = job;
    m.slot = slot;
    m.text[0] = '\0';
    if (schedule_) (void)schedule_->schedule_work(schedule_->handle, offsetof(Message, text) + 1, &m);
  }

  /// Schedules a job carrying `text`; false when it does not fit or there is no worker.
  bool schedule(Job job, std::string_view text) {
    if (!schedule_ || text.size() + 1 > kMaxText) return false;
    Message m;
    m.job = job;
    m.slot = -1;
    std::memcpy(m.text, text.data(), text.size());
    m.text[text.size()] = '\0';
    return schedule_->schedule_work(schedule_->handle, static_cast<std::uint32_t>(offsetof(Message, text) + text.size() + 1),
                                    &m) == LV2_WORKER_SUCCESS;
  }

  /// What the ports ask for: "" (no tracker), or the tracker spec (the
  /// state's, else the source port's with its port number) and, after a
  /// newline, where it sends its poses. Built in want_, whose capacity is
  /// reserved: no allocation.
  [[nodiscard]] std::string_view wanted_tracker() {
    want_.clear();
    if (control(kTracking) <= 0.5f) return want_;
    if (!tracker_spec_.empty()) {
      want_.append(tracker_spec_);
    } else {
      const int i = std::clamp(static_cast<int>(std::lround(control(kTrackerSource))), 0, 3);
      want_.append(kTrackerSources[static_cast<std::size_t>(i)]);
      if (i >= 2) {  // opentrack, osc: on the port its own port asks for
        const float fallback = i == 2 ? 4242.0f : 9000.0f;
        const long port = std::clamp(std::lround(control(i == 2 ? kOpentrackPort : kOscPort, fallback)), 1L, 65535L);
        std::array<char, 8> digits{};
        const auto r = std::to_chars(digits.data(), digits.data() + digits.size(), port);
        want_.push_back(':');
        want_.append(digits.data(), r.ptr);
      }
    }
    if (!send_spec_.empty()) {
      want_.push_back('\n');
      want_.append(send_spec_);
    }
    return want_;
  }

  /// Starts or drops the tracker when the ports changed what they ask for.
  /// tracker_requested_ has its capacity reserved: assign() does not allocate.
  void request_tracker() {
    const std::string_view want = wanted_tracker();
    if (want == std::string_view(tracker_requested_)) return;
    if (want.size() >= tracker_requested_.capacity()) return;
    if (holder_) hand_to_worker(std::move(holder_));
    if (!want.empty() && !schedule(Job::start_tracker, want)) return;  // retried next run()
    tracker_requested_.assign(want);
  }

  /// The control port's patch messages. The host's bytes are checked before
  /// they are read: every event, property and value must lie inside the
  /// sequence the host sized (patch_reader.hpp).
  void read_control_events() {
    if (!map_) return;
    read_patch_messages(
        static_cast<const LV2_Atom_Sequence*>(ports_[kControl]), uris_,
        [this] { announce_sofa_ = announce_tracker_ = announce_send_ = true; },
        [this](LV2_URID key, const LV2_Atom* value, std::string_view s) {
          if (key == uris_.sofa && value->type == uris_.atom_path) {
            (void)schedule(Job::load_hrtf, s);
          } else if (key == uris_.tracker && value->type == uris_.atom_string) {
            if (s.size() < kMaxSpec) tracker_spec_.assign(s);  // capacity reserved: no allocation
            announce_tracker_ = true;
          } else if (key == uris_.send && value->type == uris_.atom_string) {
            if (s.size() < kMaxSpec && s.find('\n') == std::string_view::npos) send_spec_.assign(s);
            announce_send_ = true;
          }
        });
  }

  /// patch:Set messages on the notify port for what changed (hosts' UIs).
  void write_notifications() {
    auto* seq = static_cast<LV2_Atom_Sequence*>(ports_[kNotify]);
    if (!seq) return;
    const std::uint32_t capacity = seq->atom.size;
    lv2_atom_forge_set_buffer(&forge_, reinterpret_cast<std::uint8_t*>(seq), capacity);
    LV2_Atom_Forge_Frame seq_frame;
    lv2_atom_forge_sequence_head(&forge_, &seq_frame, 0);
    if (announce_sofa_) announce(uris_.sofa, uris_.atom_path, panners_.current().hrtf_path());
    if (announce_tracker_) announce(uris_.tracker, uris_.atom_string, tracker_spec_);
    if (announce_send_) announce(uris_.send, uris_.atom_string, send_spec_);
    announce_sofa_ = announce_tracker_ = announce_send_ = false;
    lv2_atom_forge_pop(&forge_, &seq_frame);
  }

  void announce(LV2_URID key, LV2_URID type, const std::string& value) {
    LV2_Atom_Forge_Frame frame;
    lv2_atom_forge_frame_time(&forge_, 0);
    lv2_atom_forge_object(&forge_, &frame, 0, uris_.patch_set);
    lv2_atom_forge_key(&forge_, uris_.patch_property);
    lv2_atom_forge_urid(&forge_, key);
    lv2_atom_forge_key(&forge_, uris_.patch_value);
    lv2_atom_forge_typed_string(&forge_, type, value.c_str(), static_cast<std::uint32_t>(value.size()));
    lv2_atom_forge_pop(&forge_, &frame);
  }

  double rate_;
  std::array<void*, kPortCount> ports_{};
  const LV2_URID_Map* map_ = nullptr;
  Uris uris_{nullptr};
  LV2_Worker_Schedule* schedule_ = nullptr;
  LV2_Log_Log* log_ = nullptr;
  LV2_Log_Logger logger_{};
  LV2_Atom_Forge forge_{};

  PannerSwitch panners_;
  std::unique_ptr<LeaseHolder> holder_;
  // What crosses to and from the worker (handoff.hpp): new ones from it,
  // old ones to it.
  Handoff<BinauralPanner, kSlots> born_panners_, dead_panners_;
  Handoff<LeaseHolder, kSlots> born_holders_, dead_holders_;
  std::unique_ptr<BinauralPanner> parked_panner_;
  std::unique_ptr<LeaseHolder> parked_holder_;
  std::string tracker_spec_ = reserved(kMaxSpec);  // from state or patch:Set; "" = the source port
  std::string send_spec_ = reserved(kMaxSpec);     // where the tracker sends its poses; "" = nowhere
  std::string want_ = reserved(3 * kMaxSpec);      // wanted_tracker()'s text
  std::string tracker_requested_ = reserved(3 * kMaxSpec);  // what run() last asked the worker for
  head::HeadReader head_reader_;  // audio thread
  bool recenter_was_ = false;
  bool announce_sofa_ = false, announce_tracker_ = false, announce_send_ = false;
  Bypass bypass_{BinauralPanner::kBlock};
  bool bypass_start_ = true;

  static std::string reserved(std::size_t n) {
    std::string s;
    s.reserve(n);
    return s;
  }
};

using Glue = PluginGlue<Plugin>;

LV2_Handle instantiate(const LV2_Descriptor*, double rate, const char*, const LV2_Feature* const* features) {
  return Glue::make("earshot.lv2", rate, features);
}

const LV2_Descriptor kDescriptor = Glue::descriptor(EARSHOT_LV2_URI, instantiate);

}  // namespace
}  // namespace earshot::lv2

LV2_SYMBOL_EXPORT const LV2_Descriptor* lv2_descriptor(std::uint32_t index) {
  if (index == 0) return &earshot::lv2::kDescriptor;
  return earshot::lv2::ambi::descriptor(index - 1);  // the Ambisonic decoders, orders 1-5 (ambi_plugin.cpp)
}
