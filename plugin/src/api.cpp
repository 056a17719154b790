// The C API: handle checks, argument checks, and the calls into World.
//
// Worlds live in a fixed table of slots (the one piece of process-wide
// state the handle scheme needs; the function table itself is const). A
// handle is (generation << 8) | (slot + 1). Every call enters its world's
// slot through a Guard: it counts itself in, then checks the handle, so
// esDestroyWorld (which invalidates the handle first and then waits for
// the count to drop) never frees a world a call is still using.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"
#include "earshot/audio/room_presets.hpp"
#include "earshot/earshot.h"
#include "earshot/errors.hpp"
#include "earshot/geometry.hpp"
#include "earshot/tracker/live/tracker_options.hpp"
#include "world.hpp"

namespace earshot::plugin {
namespace {

constexpr std::size_t kMaxWorlds = 64;

struct WorldSlot {
  std::atomic<ESworld> handle{0};
  std::atomic<World*> world{nullptr};
  std::atomic<int> users{0};
  std::uint32_t generation = 0;    // under Registry::mutex
  std::unique_ptr<World> owner;    // under Registry::mutex
};

struct Registry {
  std::mutex mutex;  // create and destroy only, never esRender
  std::array<WorldSlot, kMaxWorlds> slots;
};

Registry& registry() {
  static Registry r;
  return r;
}

/// A call's hold on its world: valid() when the handle named a live world.
class Guard {
 public:
  explicit Guard(ESworld h) {
    const std::size_t i = (h & 0xFFu);
    if (h == 0 || i == 0 || i > kMaxWorlds) return;
    slot_ = &registry().slots[i - 1];
    slot_->users.fetch_add(1);
    if (slot_->handle.load() == h) world_ = slot_->world.load();
  }
  ~Guard() {
    if (slot_) slot_->users.fetch_sub(1);
  }
  Guard(const Guard&) = delete;
  Guard& operator=(const Guard&) = delete;
  [[nodiscard]] World* world() const { return world_; }

 private:
  WorldSlot* slot_ = nullptr;
  World* world_ = nullptr;
};

std::string format(const char* fmt, auto... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

ESenum fail(World& w, ESenum code, std::string message) {
  w.set_error(std::move(message));
  return code;
}

bool finite(std::initializer_list<double> v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

/// Runs `body(World&)` for a control call: handle, thread, exceptions.
template <typename Body>
ESenum control(ESworld h, const char* call, Body&& body) {
  Guard g(h);
  World* w = g.world();
  if (!w) return ES_INVALID_WORLD;
  if (!w->on_control_thread())
    return ES_WRONG_THREAD;  // the message belongs to the control thread: not written
  try {
    return body(*w);
  } catch (const Failure& f) {
    return fail(*w, f.code, std::string(call) + ": " + f.message);
  } catch (const std::bad_alloc&) {
    return fail(*w, ES_OUT_OF_MEMORY, std::string(call) + ": out of memory");
  } catch (const std::exception& e) {
    return fail(*w, ES_INVALID_VALUE, std::string(call) + ": " + e.what());
  }
}

template <typename Body>
ESenum with_source(ESworld h, ESsource s, const char* call, Body&& body) {
  return control(h, call, [&](World& w) -> ESenum {
    const auto slot = w.source_slot(s);
    if (!slot) return fail(w, ES_INVALID_SOURCE, format("%s: 0x%08x is not a source of this world", call, s));
    return body(w, w.state().sources[*slot], *slot);
  });
}

Quat quat_from_at_up6(const double* f) {
  const auto q = quat_from_at_up(Vec3{f[0], f[1], f[2]}, Vec3{f[3], f[4], f[5]});
  if (!q) throw Failure{ES_INVALID_VALUE, "'at' and 'up' must be finite, non-zero and not parallel"};
  return *q;
}

Quat normalised_quat(const float* v) {
  const auto q = normalised(Quat{v[0], v[1], v[2], v[3]});
  if (!q) throw Failure{ES_INVALID_VALUE, "the quaternion must be finite and non-zero"};
  return *q;
}

constexpr double kMaxCoordinate = 1e6;  // metres; beyond is surely a bug

Vec3 position3(const float* v, const char* what) {
  if (!finite({v[0], v[1], v[2]}))
    throw Failure{ES_INVALID_VALUE, format("%s must be finite", what)};
  for (int i = 0; i < 3; ++i)
    if (std::abs(v[i]) > kMaxCoordinate) throw Failure{ES_INVALID_VALUE, format("%s beyond 1e6 m", what)};
  return {v[0], v[1], v[2]};
}

void check_range(const char* name, double v, double lo, double hi) {
  if (!std::isfinite(v) || v < lo || v > hi)
    throw Failure{ES_INVALID_VALUE, format("%s = %g is outside [%g, %g]", name, v, lo, hi)};
}

std::optional<audio::DistanceModel> model_of(ESint m) {
  using audio::DistanceModel;
  switch (m) {
    case ES_NONE: return DistanceModel::none;
    case ES_INVERSE_DISTANCE: return DistanceModel::inverse;
    case ES_INVERSE_DISTANCE_CLAMPED: return DistanceModel::inverse_clamped;
    case ES_LINEAR_DISTANCE: return DistanceModel::linear;
    case ES_LINEAR_DISTANCE_CLAMPED: return DistanceModel::linear_clamped;
    case ES_EXPONENT_DISTANCE: return DistanceModel::exponent;
    case ES_EXPONENT_DISTANCE_CLAMPED: return DistanceModel::exponent_clamped;
    default: return std::nullopt;
  }
}

ESint enum_of(audio::DistanceModel m) {
  using audio::DistanceModel;
  switch (m) {
    case DistanceModel::none: return ES_NONE;
    case DistanceModel::inverse: return ES_INVERSE_DISTANCE;
    case DistanceModel::inverse_clamped: return ES_INVERSE_DISTANCE_CLAMPED;
    case DistanceModel::linear: return ES_LINEAR_DISTANCE;
    case DistanceModel::linear_clamped: return ES_LINEAR_DISTANCE_CLAMPED;
    case DistanceModel::exponent: return ES_EXPONENT_DISTANCE;
    case DistanceModel::exponent_clamped: return ES_EXPONENT_DISTANCE_CLAMPED;
  }
  return ES_NONE;
}

double* reverb_field(audio::RoomParams& r, ESenum p) {
  switch (p) {
    case ES_REVERB_DENSITY: return &r.density;
    case ES_REVERB_DIFFUSION: return &r.diffusion;
    case ES_REVERB_GAIN: return &r.gain;
    case ES_REVERB_GAINHF: return &r.gain_hf;
    case ES_REVERB_DECAY_TIME: return &r.decay_time_s;
    case ES_REVERB_DECAY_HFRATIO: return &r.decay_hf_ratio;
    case ES_REVERB_REFLECTIONS_GAIN: return &r.reflections_gain;
    case ES_REVERB_REFLECTIONS_DELAY: return &r.reflections_delay_s;
    case ES_REVERB_LATE_REVERB_GAIN: return &r.late_reverb_gain;
    case ES_REVERB_LATE_REVERB_DELAY: return &r.late_reverb_delay_s;
    case ES_REVERB_HFREFERENCE: return &r.hf_reference_hz;
    case ES_REVERB_WET_DB: return &r.wet_db;
    case ES_REVERB_DRY_DB: return &r.dry_db;
    default: return nullptr;
  }
}

/// Why the last esCreateWorld on this thread failed: esGetErrorMessage(0).
thread_local std::string create_error;

ESenum bad_enum(World& w, const char* call, ESenum p) {
  return fail(w, ES_INVALID_ENUM, format("%s: 0x%x is not a property this call takes", call, static_cast<unsigned>(p)));
}

}  // namespace
}  // namespace earshot::plugin

using namespace earshot::plugin;
using earshot::Quat;
using earshot::Vec3;
namespace audio = earshot::audio;

extern "C" {

ES_API const char* esGetErrorString(ESenum e) {
  switch (e) {
    case ES_OK: return "no error";
    case ES_INVALID_WORLD: return "invalid world";
    case ES_INVALID_SOURCE: return "invalid source";
    case ES_INVALID_BUFFER: return "invalid buffer";
    case ES_INVALID_ENUM: return "invalid enum";
    case ES_INVALID_VALUE: return "invalid value";
    case ES_INVALID_OPERATION: return "invalid operation";
    case ES_WRONG_THREAD: return "wrong thread";
    case ES_OUT_OF_MEMORY: return "out of memory";
    case ES_HRTF_ERROR: return "HRTF error";
    case ES_TRACKER_ERROR: return "tracker error";
    default: return "unknown error";
  }
}

ES_API void esWorldParamsDefault(ESworldparams* p) {
  if (!p) return;
  *p = ESworldparams{};
  p->size = sizeof(ESworldparams);
  p->sample_rate = 48000;
  p->block_size = 128;
  p->max_sources = 64;
  p->max_buffers = 256;
  p->doppler_factor = 1.0f;
  p->speed_of_sound = 343.3f;
  p->propagation_delay = ES_FALSE;
  p->late_reverb = ES_REVERB_FDN;
  p->head_radius_m = 0.0f;
  p->hrtf_path = nullptr;
}

ES_API ESenum esCreateWorld(const ESworldparams* params, ESworld* out) {
  if (!params || !out || params->size != sizeof(ESworldparams)) {
    create_error = "esCreateWorld: params or world is NULL, or params->size is not sizeof(ESworldparams)";
    return ES_INVALID_VALUE;
  }
  *out = 0;
  const ESworldparams& p = *params;
  if (p.sample_rate < 8000 || p.sample_rate > 192000 || p.block_size < 1 || p.block_size > 8192 ||
      p.max_sources < 1 || p.max_sources > 256 || p.max_buffers < 1 || p.max_buffers > 4096 ||
      !std::isfinite(p.doppler_factor) || p.doppler_factor < 0 || p.doppler_factor > 100 ||
      !std::isfinite(p.speed_of_sound) || p.speed_of_sound < 1 || p.speed_of_sound > 1e5 ||
      (p.propagation_delay != ES_FALSE && p.propagation_delay != ES_TRUE) ||
      (p.late_reverb != ES_REVERB_FDN && p.late_reverb != ES_REVERB_SCHROEDER) || !std::isfinite(p.head_radius_m) ||
      (p.head_radius_m != 0.0f && (p.head_radius_m < 0.01f || p.head_radius_m > 0.5f))) {
    create_error = format(
        "esCreateWorld: a parameter is out of range: sample_rate %u (8000..192000), block_size %u (1..8192), "
        "max_sources %u (1..256), max_buffers %u (1..4096), doppler_factor %g (0..100), speed_of_sound %g "
        "(1..1e5), propagation_delay %d, late_reverb 0x%x, head_radius_m %g (0 or 0.01..0.5)",
        p.sample_rate, p.block_size, p.max_sources, p.max_buffers, double(p.doppler_factor),
        double(p.speed_of_sound), int(p.propagation_delay), unsigned(p.late_reverb), double(p.head_radius_m));
    return ES_INVALID_VALUE;
  }
  std::unique_ptr<World> w;
  try {
    w = std::make_unique<World>(p);
  } catch (const Failure& f) {
    create_error = f.message;  // e.g. the SOFA file's own error, naming it
    return f.code;
  } catch (const std::bad_alloc&) {
    create_error = "esCreateWorld: out of memory";
    return ES_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    create_error = std::string("esCreateWorld: ") + e.what();
    return ES_INVALID_VALUE;
  }
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  for (std::size_t i = 0; i < kMaxWorlds; ++i) {
    WorldSlot& s = r.slots[i];
    if (s.owner) continue;
    s.generation = (s.generation + 1) & 0xFFFFFFu;
    if (s.generation == 0) s.generation = 1;
    const ESworld h = (s.generation << 8) | static_cast<ESworld>(i + 1);
    s.world.store(w.get());
    s.owner = std::move(w);
    s.handle.store(h);
    *out = h;
    return ES_OK;
  }
  create_error = format("esCreateWorld: %zu worlds exist, the most there can be", kMaxWorlds);
  return ES_OUT_OF_MEMORY;
}

ES_API ESenum esDestroyWorld(ESworld h) {
  const std::size_t i = (h & 0xFFu);
  if (h == 0 || i == 0 || i > kMaxWorlds) return ES_INVALID_WORLD;
  Registry& r = registry();
  std::unique_ptr<World> dead;
  {
    std::lock_guard lock(r.mutex);
    WorldSlot& s = r.slots[i - 1];
    if (s.handle.load() != h) return ES_INVALID_WORLD;
    if (!s.owner->on_control_thread()) return ES_WRONG_THREAD;
    if (s.owner->rendering_here()) return ES_INVALID_OPERATION;  // from a callback: would wait for itself
    s.handle.store(0);                                          // no new call gets in
    while (s.users.load() != 0) std::this_thread::yield();      // calls inside finish
    s.world.store(nullptr);
    dead = std::move(s.owner);
  }
  return ES_OK;  // `dead` stops its tracker and frees everything here
}

ES_API ESenum esSetControlThread(ESworld h) {
  Guard g(h);
  if (!g.world()) return ES_INVALID_WORLD;
  g.world()->set_control_thread();
  return ES_OK;
}

ES_API const char* esGetErrorMessage(ESworld h) {
  if (h == 0) return create_error.c_str();  // any thread: its own last esCreateWorld
  Guard g(h);
  if (!g.world()) return "invalid world handle";
  if (!g.world()->on_control_thread()) return "not the world's control thread";
  return g.world()->error();
}

ES_API ESenum esWorldi(ESworld h, ESenum param, ESint value) {
  return control(h, "esWorldi", [&](World& w) -> ESenum {
    if (param == ES_HEAD_PREDICTION) {
      if (value != ES_TRUE && value != ES_FALSE)
        return fail(w, ES_INVALID_VALUE, "esWorldi: ES_HEAD_PREDICTION takes ES_TRUE or ES_FALSE");
      w.set_head_prediction(value == ES_TRUE, w.host_latency_s());
      return ES_OK;
    }
    if (param == ES_OUTPUT_LATENCY_US) {
      if (value < 0 || value > 1000000)
        return fail(w, ES_INVALID_VALUE, "esWorldi: ES_OUTPUT_LATENCY_US must be 0..1000000 microseconds");
      w.set_head_prediction(w.head_prediction(), static_cast<double>(value) * 1e-6);
      return ES_OK;
    }
    if (param == ES_QUALITY) {
      const ESint order = value - ES_QUALITY_DIRECT;  // 0 direct, N ambisonic:N
      if (order < 0 || order > ES_MAX_AMBISONIC_ORDER)
        return fail(w, ES_INVALID_VALUE, "esWorldi: ES_QUALITY takes ES_QUALITY_DIRECT or ES_QUALITY_AMBISONIC(1..7)");
      w.set_quality(order);  // Failure names a set that cannot carry the order
      return ES_OK;
    }
    if (param == ES_AMBISONIC_DECODER) {
      if (value != ES_DECODER_MAGLS && value != ES_DECODER_LS)
        return fail(w, ES_INVALID_VALUE, "esWorldi: ES_AMBISONIC_DECODER takes ES_DECODER_MAGLS or ES_DECODER_LS");
      w.set_decoder_method(value == ES_DECODER_LS ? earshot::ambisonics::DecoderMethod::ls
                                                  : earshot::ambisonics::DecoderMethod::magls);
      return ES_OK;
    }
    if (param != ES_COMMIT_MODE) return bad_enum(w, "esWorldi", param);
    if (value != ES_IMMEDIATE && value != ES_DEFERRED)
      return fail(w, ES_INVALID_VALUE, "esWorldi: ES_COMMIT_MODE takes ES_IMMEDIATE or ES_DEFERRED");
    const bool was_deferred = w.deferred();
    w.set_commit_mode(value == ES_DEFERRED);
    if (was_deferred && value == ES_IMMEDIATE) w.commit();  // pending changes apply now
    return ES_OK;
  });
}

ES_API ESenum esGetWorldi(ESworld h, ESenum param, ESint* value) {
  return control(h, "esGetWorldi", [&](World& w) -> ESenum {
    if (!value) return fail(w, ES_INVALID_VALUE, "esGetWorldi: value is NULL");
    switch (param) {
      case ES_COMMIT_MODE: *value = w.deferred() ? ES_DEFERRED : ES_IMMEDIATE; return ES_OK;
      case ES_SAMPLE_RATE: *value = static_cast<ESint>(w.params().sample_rate); return ES_OK;
      case ES_BLOCK_SIZE: *value = static_cast<ESint>(w.params().block_size); return ES_OK;
      case ES_MAX_SOURCES: *value = static_cast<ESint>(w.params().max_sources); return ES_OK;
      case ES_BLOCKS_RENDERED:
        *value = static_cast<ESint>(std::min<std::uint64_t>(w.blocks_rendered(), 0x7FFFFFFF));
        return ES_OK;
      case ES_HEAD_PREDICTION: *value = w.head_prediction() ? ES_TRUE : ES_FALSE; return ES_OK;
      case ES_OUTPUT_LATENCY_US: *value = static_cast<ESint>(std::lround(w.host_latency_s() * 1e6)); return ES_OK;
      case ES_QUALITY: *value = ES_QUALITY_DIRECT + w.quality(); return ES_OK;
      case ES_AMBISONIC_DECODER:
        *value = w.decoder_method() == earshot::ambisonics::DecoderMethod::ls ? ES_DECODER_LS : ES_DECODER_MAGLS;
        return ES_OK;
      default: return bad_enum(w, "esGetWorldi", param);
    }
  });
}

ES_API ESenum esDopplerFactor(ESworld h, ESfloat f) {
  return control(h, "esDopplerFactor", [&](World& w) -> ESenum {
    check_range("esDopplerFactor: factor", f, 0.0, 100.0);
    if (w.propagation_delay())
      return fail(w, ES_INVALID_OPERATION, "esDopplerFactor: fixed at esCreateWorld with propagation_delay");
    w.state().doppler_factor = f;
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esSpeedOfSound(ESworld h, ESfloat c) {
  return control(h, "esSpeedOfSound", [&](World& w) -> ESenum {
    check_range("esSpeedOfSound: speed", c, 1.0, 1e5);
    if (w.propagation_delay())
      return fail(w, ES_INVALID_OPERATION, "esSpeedOfSound: fixed at esCreateWorld with propagation_delay");
    w.state().speed_of_sound = c;
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esCommit(ESworld h) {
  return control(h, "esCommit", [&](World& w) -> ESenum {
    w.commit();
    return ES_OK;
  });
}

// ---- listener ----

ES_API ESenum esListenerfv(ESworld h, ESenum param, const ESfloat* v) {
  return control(h, "esListenerfv", [&](World& w) -> ESenum {
    if (!v) return fail(w, ES_INVALID_VALUE, "esListenerfv: values is NULL");
    Snapshot& s = w.state();
    switch (param) {
      case ES_POSITION: s.listener.position = position3(v, "esListenerfv: ES_POSITION"); break;
      case ES_VELOCITY: s.listener_velocity = position3(v, "esListenerfv: ES_VELOCITY"); break;
      case ES_GAIN: check_range("esListenerfv: ES_GAIN", v[0], 0.0, 1e3); s.listener_gain = v[0]; break;
      case ES_ORIENTATION: {
        const double f[6] = {v[0], v[1], v[2], v[3], v[4], v[5]};
        if (!finite({f[0], f[1], f[2], f[3], f[4], f[5]}))
          return fail(w, ES_INVALID_VALUE, "esListenerfv: ES_ORIENTATION must be finite");
        s.listener.orientation = quat_from_at_up6(f);
        break;
      }
      case ES_ORIENTATION_QUAT: s.listener.orientation = normalised_quat(v); break;
      default: return bad_enum(w, "esListenerfv", param);
    }
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esListenerf(ESworld h, ESenum param, ESfloat value) {
  if (param != ES_GAIN) {
    return control(h, "esListenerf", [&](World& w) { return bad_enum(w, "esListenerf", param); });
  }
  return esListenerfv(h, param, &value);
}

ES_API ESenum esListener3f(ESworld h, ESenum param, ESfloat x, ESfloat y, ESfloat z) {
  if (param != ES_POSITION && param != ES_VELOCITY)
    return control(h, "esListener3f", [&](World& w) { return bad_enum(w, "esListener3f", param); });
  const ESfloat v[3] = {x, y, z};
  return esListenerfv(h, param, v);
}

ES_API ESenum esGetListenerfv(ESworld h, ESenum param, ESfloat* v) {
  return control(h, "esGetListenerfv", [&](World& w) -> ESenum {
    if (!v) return fail(w, ES_INVALID_VALUE, "esGetListenerfv: values is NULL");
    const Snapshot& s = w.state();
    auto put = [&](std::initializer_list<double> xs) {
      std::size_t i = 0;
      for (double x : xs) v[i++] = static_cast<ESfloat>(x);
    };
    const auto& p = s.listener.position;
    const auto& q = s.listener.orientation;
    switch (param) {
      case ES_POSITION: put({p[0], p[1], p[2]}); return ES_OK;
      case ES_VELOCITY: put({s.listener_velocity[0], s.listener_velocity[1], s.listener_velocity[2]}); return ES_OK;
      case ES_GAIN: put({s.listener_gain}); return ES_OK;
      case ES_ORIENTATION_QUAT: put({q[0], q[1], q[2], q[3]}); return ES_OK;
      case ES_ORIENTATION: {
        // at = R (0, 0, -1), up = R (0, 1, 0)
        const double w0 = q[0], x = q[1], y = q[2], z = q[3];
        put({-(2 * (x * z + w0 * y)), -(2 * (y * z - w0 * x)), -(1 - 2 * (x * x + y * y)),
             2 * (x * y - w0 * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w0 * x)});
        return ES_OK;
      }
      default: return bad_enum(w, "esGetListenerfv", param);
    }
  });
}

// ---- buffers ----

ES_API ESenum esCreateBuffer(ESworld h, const float* samples, ESuint frames, ESuint rate, ESbuffer* out) {
  return control(h, "esCreateBuffer", [&](World& w) -> ESenum {
    if (!out) return fail(w, ES_INVALID_VALUE, "esCreateBuffer: buffer is NULL");
    *out = 0;
    if (!samples && frames > 0) return fail(w, ES_INVALID_VALUE, "esCreateBuffer: samples is NULL");
    if (frames == 0 || frames > (1u << 28))
      return fail(w, ES_INVALID_VALUE, format("esCreateBuffer: %u frames (1 to 2^28)", frames));
    if (rate < 1000 || rate > 768000)
      return fail(w, ES_INVALID_VALUE, format("esCreateBuffer: sample rate %u Hz (1000 to 768000)", rate));
    const ESbuffer b = w.create_buffer(samples, frames, rate);
    if (b == 0) return fail(w, ES_OUT_OF_MEMORY, "esCreateBuffer: max_buffers are in use");
    *out = b;
    return ES_OK;
  });
}

ES_API ESenum esDeleteBuffer(ESworld h, ESbuffer b) {
  return control(h, "esDeleteBuffer", [&](World& w) -> ESenum {
    if (!w.buffer(b)) return fail(w, ES_INVALID_BUFFER, format("esDeleteBuffer: 0x%08x is not a buffer of this world", b));
    if (!w.delete_buffer(b)) return fail(w, ES_INVALID_OPERATION, "esDeleteBuffer: a source still has it set");
    return ES_OK;
  });
}

// ---- sources ----

ES_API ESenum esCreateSource(ESworld h, ESsource* out) {
  return control(h, "esCreateSource", [&](World& w) -> ESenum {
    if (!out) return fail(w, ES_INVALID_VALUE, "esCreateSource: source is NULL");
    *out = w.create_source();
    if (*out == 0) return fail(w, ES_OUT_OF_MEMORY, "esCreateSource: max_sources are in use");
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esDeleteSource(ESworld h, ESsource s) {
  return with_source(h, s, "esDeleteSource", [&](World& w, SourceParams&, std::size_t slot) -> ESenum {
    w.delete_source(slot);
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esSourcefv(ESworld h, ESsource s, ESenum param, const ESfloat* v) {
  return with_source(h, s, "esSourcefv", [&](World& w, SourceParams& sp, std::size_t) -> ESenum {
    if (!v) return fail(w, ES_INVALID_VALUE, "esSourcefv: values is NULL");
    audio::SourceState& st = sp.state;
    const double x = v[0];
    switch (param) {
      case ES_POSITION: st.position = position3(v, "esSourcefv: ES_POSITION"); break;
      case ES_VELOCITY: sp.velocity = position3(v, "esSourcefv: ES_VELOCITY"); break;
      case ES_DIRECTION: st.cone.direction = position3(v, "esSourcefv: ES_DIRECTION"); break;
      case ES_GAIN: check_range("ES_GAIN", x, 0.0, 1e3); st.gain = x; break;
      case ES_MIN_GAIN: check_range("ES_MIN_GAIN", x, 0.0, 1.0); st.min_gain = x; break;
      case ES_MAX_GAIN: check_range("ES_MAX_GAIN", x, 0.0, 1.0); st.max_gain = x; break;
      case ES_PITCH: check_range("ES_PITCH", x, 1.0 / 16.0, 16.0); sp.pitch = x; break;
      case ES_REFERENCE_DISTANCE: check_range("ES_REFERENCE_DISTANCE", x, 0.0, 1e6); st.distance.reference_distance = x; break;
      case ES_ROLLOFF_FACTOR: check_range("ES_ROLLOFF_FACTOR", x, 0.0, 1e3); st.distance.rolloff = x; break;
      case ES_MAX_DISTANCE:
        check_range("ES_MAX_DISTANCE", x, 0.0, std::numeric_limits<float>::max());
        st.distance.max_distance = x;
        break;
      case ES_CONE_INNER_ANGLE: check_range("ES_CONE_INNER_ANGLE", x, 0.0, 360.0); st.cone.inner_angle_deg = x; break;
      case ES_CONE_OUTER_ANGLE: check_range("ES_CONE_OUTER_ANGLE", x, 0.0, 360.0); st.cone.outer_angle_deg = x; break;
      case ES_CONE_OUTER_GAIN: check_range("ES_CONE_OUTER_GAIN", x, 0.0, 1.0); st.cone.outer_gain = x; break;
      case ES_REVERB_SEND: check_range("ES_REVERB_SEND", x, 0.0, 10.0); st.reverb_send = x; break;
      case ES_AIR_ABSORPTION_FACTOR: check_range("ES_AIR_ABSORPTION_FACTOR", x, 0.0, 10.0); st.air_absorption = x; break;
      case ES_ORIENTATION: {  // a field's orientation (ABI 1.5)
        const double f[6] = {v[0], v[1], v[2], v[3], v[4], v[5]};
        if (!finite({f[0], f[1], f[2], f[3], f[4], f[5]}))
          return fail(w, ES_INVALID_VALUE, "esSourcefv: ES_ORIENTATION must be finite");
        sp.orientation = quat_from_at_up6(f);
        break;
      }
      case ES_ORIENTATION_QUAT: sp.orientation = normalised_quat(v); break;
      default: return bad_enum(w, "esSourcefv", param);
    }
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esSourcef(ESworld h, ESsource s, ESenum param, ESfloat value) {
  if (param == ES_POSITION || param == ES_VELOCITY || param == ES_DIRECTION || param == ES_ORIENTATION ||
      param == ES_ORIENTATION_QUAT)
    return with_source(h, s, "esSourcef", [&](World& w, SourceParams&, std::size_t) { return bad_enum(w, "esSourcef", param); });
  return esSourcefv(h, s, param, &value);
}

ES_API ESenum esSource3f(ESworld h, ESsource s, ESenum param, ESfloat x, ESfloat y, ESfloat z) {
  if (param != ES_POSITION && param != ES_VELOCITY && param != ES_DIRECTION)
    return with_source(h, s, "esSource3f", [&](World& w, SourceParams&, std::size_t) { return bad_enum(w, "esSource3f", param); });
  const ESfloat v[3] = {x, y, z};
  return esSourcefv(h, s, param, v);
}

ES_API ESenum esSourcei(ESworld h, ESsource s, ESenum param, ESint value) {
  return with_source(h, s, "esSourcei", [&](World& w, SourceParams& sp, std::size_t slot) -> ESenum {
    switch (param) {
      case ES_SOURCE_RELATIVE:
      case ES_LOOPING:
        if (value != ES_TRUE && value != ES_FALSE) return fail(w, ES_INVALID_VALUE, "esSourcei: ES_TRUE or ES_FALSE");
        (param == ES_LOOPING ? sp.looping : sp.state.relative) = value == ES_TRUE;
        break;
      case ES_DISTANCE_MODEL: {
        const auto m = model_of(value);
        if (!m) return fail(w, ES_INVALID_VALUE, format("esSourcei: 0x%x is not a distance model", static_cast<unsigned>(value)));
        sp.state.distance.model = *m;
        break;
      }
      case ES_BUFFER: {
        const auto b = static_cast<ESbuffer>(value);
        if (b != 0 && !w.buffer(b))
          return fail(w, ES_INVALID_BUFFER, format("esSourcei: 0x%08x is not a buffer of this world", b));
        if (const ESenum now = w.source_state(slot); now == ES_PLAYING || now == ES_PAUSED)
          return fail(w, ES_INVALID_OPERATION, "esSourcei: ES_BUFFER on a playing or paused source (stop it first)");
        if (b == 0) {
          sp.buffer = 0;
          sp.data = nullptr;
          sp.frames = 0;
          if (!sp.field_callback) sp.order = 0;
          break;
        }
        const auto info = w.buffer(b);
        if (!info) return fail(w, ES_INVALID_BUFFER, format("esSourcei: 0x%08x is not a buffer of this world", b));
        w.prepare_bed(slot, info->order);  // a field's decoder (may design it: throws, nothing changed)
        sp.order = info->order;
        sp.field_callback = nullptr;
        sp.buffer = b;
        sp.data = info->data;
        sp.frames = info->frames;
        sp.rate_ratio = info->rate_ratio;
        sp.callback = nullptr;
        sp.user = nullptr;
        break;
      }
      default: return bad_enum(w, "esSourcei", param);
    }
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esGetSourcefv(ESworld h, ESsource s, ESenum param, ESfloat* v) {
  return with_source(h, s, "esGetSourcefv", [&](World& w, SourceParams& sp, std::size_t slot) -> ESenum {
    if (!v) return fail(w, ES_INVALID_VALUE, "esGetSourcefv: values is NULL");
    const audio::SourceState& st = sp.state;
    auto put3 = [&](const Vec3& x) {
      for (int i = 0; i < 3; ++i) v[i] = static_cast<ESfloat>(x[i]);
    };
    double x = 0.0;
    switch (param) {
      case ES_POSITION: put3(st.position); return ES_OK;
      case ES_VELOCITY: put3(sp.velocity); return ES_OK;
      case ES_DIRECTION: put3(st.cone.direction); return ES_OK;
      case ES_GAIN: x = st.gain; break;
      case ES_MIN_GAIN: x = st.min_gain; break;
      case ES_MAX_GAIN: x = st.max_gain; break;
      case ES_PITCH: x = sp.pitch; break;
      case ES_REFERENCE_DISTANCE: x = st.distance.reference_distance; break;
      case ES_ROLLOFF_FACTOR: x = st.distance.rolloff; break;
      case ES_MAX_DISTANCE: x = std::min<double>(st.distance.max_distance, std::numeric_limits<float>::max()); break;
      case ES_CONE_INNER_ANGLE: x = st.cone.inner_angle_deg; break;
      case ES_CONE_OUTER_ANGLE: x = st.cone.outer_angle_deg; break;
      case ES_CONE_OUTER_GAIN: x = st.cone.outer_gain; break;
      case ES_REVERB_SEND: x = st.reverb_send; break;
      case ES_AIR_ABSORPTION_FACTOR: x = st.air_absorption; break;
      case ES_SAMPLE_OFFSET: x = w.source_offset(slot); break;
      case ES_ORIENTATION_QUAT: {
        const Quat& q = sp.orientation;
        for (int i = 0; i < 4; ++i) v[i] = static_cast<ESfloat>(q[static_cast<std::size_t>(i)]);
        return ES_OK;
      }
      case ES_ORIENTATION: {  // at = R (0, 0, -1), up = R (0, 1, 0)
        const Vec3 at = earshot::rotate(sp.orientation, Vec3{0, 0, -1}), up = earshot::rotate(sp.orientation, Vec3{0, 1, 0});
        for (int i = 0; i < 3; ++i) {
          v[i] = static_cast<ESfloat>(at[static_cast<std::size_t>(i)]);
          v[i + 3] = static_cast<ESfloat>(up[static_cast<std::size_t>(i)]);
        }
        return ES_OK;
      }
      default: return bad_enum(w, "esGetSourcefv", param);
    }
    v[0] = static_cast<ESfloat>(x);
    return ES_OK;
  });
}

ES_API ESenum esGetSourcef(ESworld h, ESsource s, ESenum param, ESfloat* value) {
  if (param == ES_POSITION || param == ES_VELOCITY || param == ES_DIRECTION || param == ES_ORIENTATION ||
      param == ES_ORIENTATION_QUAT)
    return with_source(h, s, "esGetSourcef", [&](World& w, SourceParams&, std::size_t) { return bad_enum(w, "esGetSourcef", param); });
  return esGetSourcefv(h, s, param, value);
}

ES_API ESenum esGetSourcei(ESworld h, ESsource s, ESenum param, ESint* value) {
  return with_source(h, s, "esGetSourcei", [&](World& w, SourceParams& sp, std::size_t slot) -> ESenum {
    if (!value) return fail(w, ES_INVALID_VALUE, "esGetSourcei: value is NULL");
    switch (param) {
      case ES_SOURCE_RELATIVE: *value = sp.state.relative ? ES_TRUE : ES_FALSE; return ES_OK;
      case ES_LOOPING: *value = sp.looping ? ES_TRUE : ES_FALSE; return ES_OK;
      case ES_DISTANCE_MODEL: *value = enum_of(sp.state.distance.model); return ES_OK;
      case ES_BUFFER: *value = static_cast<ESint>(sp.buffer); return ES_OK;
      case ES_SOURCE_STATE: *value = w.source_state(slot); return ES_OK;
      case ES_SAMPLE_OFFSET: *value = static_cast<ESint>(w.source_offset(slot)); return ES_OK;
      case ES_AMBISONIC_ORDER: *value = sp.order; return ES_OK;
      default: return bad_enum(w, "esGetSourcei", param);
    }
  });
}

ES_API ESenum esSourceCallback(ESworld h, ESsource s, ESsourcecallback cb, void* user) {
  return with_source(h, s, "esSourceCallback", [&](World& w, SourceParams& sp, std::size_t) -> ESenum {
    sp.callback = cb;
    sp.user = cb ? user : nullptr;
    if (cb) {
      sp.buffer = 0;
      sp.data = nullptr;
      sp.frames = 0;
    }
    if (cb) {  // a mono callback: a point source again
      sp.field_callback = nullptr;
      sp.order = 0;
    }
    w.changed();
    return ES_OK;
  });
}

namespace {
ESenum play_state(ESworld h, ESsource s, const char* call, ESenum to) {
  return with_source(h, s, call, [&](World& w, SourceParams& sp, std::size_t slot) -> ESenum {
    const ESenum now = w.source_state(slot);
    if (to == ES_PAUSED && now != ES_PLAYING) return ES_OK;  // OpenAL: pausing a non-playing source does nothing
    if (to == ES_PLAYING && now == ES_PAUSED) {
      sp.play_state = ES_PLAYING;  // resume: the audio side keeps the position
    } else {
      sp.play_state = to;
    }
    ++sp.play_serial;
    w.changed();
    return ES_OK;
  });
}
}  // namespace

ES_API ESenum esSourcePlay(ESworld h, ESsource s) { return play_state(h, s, "esSourcePlay", ES_PLAYING); }
ES_API ESenum esSourcePause(ESworld h, ESsource s) { return play_state(h, s, "esSourcePause", ES_PAUSED); }
ES_API ESenum esSourceStop(ESworld h, ESsource s) { return play_state(h, s, "esSourceStop", ES_STOPPED); }
ES_API ESenum esSourceRewind(ESworld h, ESsource s) { return play_state(h, s, "esSourceRewind", ES_INITIAL); }

// ---- reverb ----

ES_API ESenum esReverbPreset(ESworld h, const char* name) {
  return control(h, "esReverbPreset", [&](World& w) -> ESenum {
    if (!name) return fail(w, ES_INVALID_VALUE, "esReverbPreset: name is NULL");
    Snapshot& s = w.state();
    s.room = audio::room_preset(name);  // InputError lists the valid names
    ++s.room_serial;
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esReverbf(ESworld h, ESenum param, ESfloat value) {
  return control(h, "esReverbf", [&](World& w) -> ESenum {
    Snapshot& s = w.state();
    audio::RoomParams r = s.room;
    double* f = reverb_field(r, param);
    if (!f) return bad_enum(w, "esReverbf", param);
    if (!std::isfinite(value)) return fail(w, ES_INVALID_VALUE, "esReverbf: value must be finite");
    *f = value;
    audio::validate(r);  // InputError names the field and its range
    s.room = r;
    ++s.room_serial;
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esReverbi(ESworld h, ESenum param, ESint value) {
  return control(h, "esReverbi", [&](World& w) -> ESenum {
    if (param != ES_REVERB_ENABLED) return bad_enum(w, "esReverbi", param);
    if (value != ES_TRUE && value != ES_FALSE) return fail(w, ES_INVALID_VALUE, "esReverbi: ES_TRUE or ES_FALSE");
    w.state().reverb_enabled = value == ES_TRUE;
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esGetReverbf(ESworld h, ESenum param, ESfloat* value) {
  return control(h, "esGetReverbf", [&](World& w) -> ESenum {
    if (!value) return fail(w, ES_INVALID_VALUE, "esGetReverbf: value is NULL");
    if (param == ES_REVERB_ENABLED) {
      *value = w.state().reverb_enabled ? 1.0f : 0.0f;
      return ES_OK;
    }
    audio::RoomParams r = w.state().room;
    const double* f = reverb_field(r, param);
    if (!f) return bad_enum(w, "esGetReverbf", param);
    *value = static_cast<ESfloat>(*f);
    return ES_OK;
  });
}

// ---- tracking ----

ES_API ESenum esAttachTracker(ESworld h, const char* spec) {
  return control(h, "esAttachTracker", [&](World& w) -> ESenum {
    w.attach_tracker(spec);
    return ES_OK;
  });
}

ES_API ESenum esAttachTrackerEx(ESworld h, const char* spec, const char* const* options) {
  return control(h, "esAttachTrackerEx", [&](World& w) -> ESenum {
    // The pairs as strings; their meaning is the tracker library's (one
    // parser for every host: tracker/live/tracker_options.hpp).
    std::vector<std::pair<std::string, std::string>> pairs;
    for (std::size_t i = 0; options && options[i]; i += 2) {
      if (pairs.size() == ES_TRACKER_MAX_OPTIONS)
        return fail(w, ES_INVALID_VALUE,
                    format("esAttachTrackerEx: more than %d options (is the list NULL-terminated?)", ES_TRACKER_MAX_OPTIONS));
      if (!options[i + 1])
        return fail(w, ES_INVALID_VALUE, format("esAttachTrackerEx: option '%s' has no value (NULL)", options[i]));
      pairs.emplace_back(options[i], options[i + 1]);
    }
    earshot::tracker::TrackerOptions parsed;
    try {
      parsed = earshot::tracker::parse_tracker_options(pairs, "esAttachTrackerEx");
    } catch (const earshot::InputError& e) {
      return fail(w, ES_INVALID_VALUE, e.what());
    }
    w.attach_tracker(spec, parsed);
    return ES_OK;
  });
}

ES_API ESenum esWorldHrtf(ESworld h, const char* sofa_path) {
  return control(h, "esWorldHrtf", [&](World& w) -> ESenum {
    w.set_hrtf(sofa_path);  // Failure(ES_HRTF_ERROR) names the file
    return ES_OK;
  });
}

ES_API ESenum esRecenter(ESworld h) {
  return control(h, "esRecenter", [&](World& w) -> ESenum {
    w.recenter();
    return ES_OK;
  });
}

ES_API ESenum esGetHeadPose(ESworld h, ESfloat* position, ESfloat* orientation) {
  Guard g(h);
  if (!g.world()) return ES_INVALID_WORLD;
  if (!position || !orientation) return ES_INVALID_VALUE;
  const earshot::HeadPose p = g.world()->head_pose();
  for (int i = 0; i < 3; ++i) position[i] = static_cast<ESfloat>(p.position[static_cast<std::size_t>(i)]);
  for (int i = 0; i < 4; ++i) orientation[i] = static_cast<ESfloat>(p.orientation[static_cast<std::size_t>(i)]);
  return ES_OK;
}

ES_API ESenum esSetHeadPose(ESworld h, const ESfloat* position, const ESfloat* orientation) {
  return control(h, "esSetHeadPose", [&](World& w) -> ESenum {
    if (!position || !orientation) return fail(w, ES_INVALID_VALUE, "esSetHeadPose: NULL pointer");
    const Vec3 p = position3(position, "esSetHeadPose: position");
    const Quat q = normalised_quat(orientation);
    w.state().head_position = p;
    w.state().head_orientation = q;
    w.changed();
    return ES_OK;
  });
}

ES_API ESenum esGetTrackerState(ESworld h, EStrackerstate* state) {
  return control(h, "esGetTrackerState", [&](World& w) -> ESenum {
    if (!state) return fail(w, ES_INVALID_VALUE, "esGetTrackerState: NULL pointer");
    if (state->size < sizeof(EStrackerstate))
      return fail(w, ES_INVALID_VALUE,
                  format("esGetTrackerState: state->size = %u, expected sizeof(EStrackerstate) = %zu",
                         state->size, sizeof(EStrackerstate)));
    w.tracker_state(*state);
    return ES_OK;
  });
}

ES_API ESenum esGetTrackerImage(ESworld h, EStrackerimage* image) {
  return control(h, "esGetTrackerImage", [&](World& w) -> ESenum {
    if (!image) return fail(w, ES_INVALID_VALUE, "esGetTrackerImage: NULL pointer");
    if (image->size < sizeof(EStrackerimage))
      return fail(w, ES_INVALID_VALUE,
                  format("esGetTrackerImage: image->size = %u, expected sizeof(EStrackerimage) = %zu",
                         image->size, sizeof(EStrackerimage)));
    w.tracker_image(*image);
    return ES_OK;
  });
}

// ---- rendering ----

ES_API ESenum esRender(ESworld h, float* left, float* right, ESuint frames) {
  Guard g(h);
  World* w = g.world();
  if (!w) return ES_INVALID_WORLD;
  if (!left || !right || frames != w->params().block_size) return ES_INVALID_VALUE;
  if (!w->begin_render()) return ES_WRONG_THREAD;
  w->render(left, right);
  w->end_render();
  return ES_OK;
}

// ---- Ambisonic fields (ABI 1.5) ----

ES_API ESenum esCreateAmbisonicBuffer(ESworld h, const float* samples, ESuint frames, ESuint rate, ESuint order,
                                      ESenum layout, ESenum scaling, ESbuffer* out) {
  return control(h, "esCreateAmbisonicBuffer", [&](World& w) -> ESenum {
    constexpr const char* call = "esCreateAmbisonicBuffer";
    if (!out) return fail(w, ES_INVALID_VALUE, format("%s: buffer is NULL", call));
    *out = 0;
    if (order < 1 || order > ES_MAX_AMBISONIC_ORDER)
      return fail(w, ES_INVALID_VALUE, format("%s: order %u (1 to %d)", call, order, ES_MAX_AMBISONIC_ORDER));
    if (layout != ES_AMBISONIC_LAYOUT_ACN && layout != ES_AMBISONIC_LAYOUT_FUMA)
      return fail(w, ES_INVALID_VALUE, format("%s: layout 0x%x (ES_AMBISONIC_LAYOUT_ACN or _FUMA)", call, unsigned(layout)));
    if (scaling != ES_AMBISONIC_SCALING_SN3D && scaling != ES_AMBISONIC_SCALING_N3D && scaling != ES_AMBISONIC_SCALING_FUMA)
      return fail(w, ES_INVALID_VALUE,
                  format("%s: scaling 0x%x (ES_AMBISONIC_SCALING_SN3D, _N3D or _FUMA)", call, unsigned(scaling)));
    if ((layout == ES_AMBISONIC_LAYOUT_FUMA || scaling == ES_AMBISONIC_SCALING_FUMA) && order > 3)
      return fail(w, ES_INVALID_VALUE, format("%s: FuMa stops at order 3 (order %u)", call, order));
    const std::size_t channels = std::size_t(order + 1) * std::size_t(order + 1);
    if (!samples) return fail(w, ES_INVALID_VALUE, format("%s: samples is NULL", call));
    if (frames == 0 || std::size_t(frames) * channels > (std::size_t{1} << 28))
      return fail(w, ES_INVALID_VALUE, format("%s: %u frames of %zu channels (1 to 2^28 samples)", call, frames, channels));
    if (rate < 1000 || rate > 768000)
      return fail(w, ES_INVALID_VALUE, format("%s: sample rate %u Hz (1000 to 768000)", call, rate));
    // ambiX channel n = gain[n] x the caller's channel source[n]: the
    // layout says where channel n is, the scaling how loud.
    namespace ambi = earshot::ambisonics;
    const int N = static_cast<int>(order);
    const ambi::ChannelMap where =
        ambi::to_ambix(layout == ES_AMBISONIC_LAYOUT_FUMA ? ambi::Convention::fuma : ambi::Convention::ambix, N);
    const ambi::ChannelMap loud = ambi::to_ambix(scaling == ES_AMBISONIC_SCALING_FUMA  ? ambi::Convention::fuma
                                                 : scaling == ES_AMBISONIC_SCALING_N3D ? ambi::Convention::n3d
                                                                                       : ambi::Convention::ambix,
                                                 N);
    std::vector<float> planar(channels * frames);
    for (std::size_t c = 0; c < channels; ++c) {
      const std::size_t from = where.source[c];
      const auto g = static_cast<float>(loud.gain[c]);
      float* dst = planar.data() + c * frames;
      for (std::size_t i = 0; i < frames; ++i) dst[i] = g * samples[i * channels + from];
    }
    const ESbuffer b = w.create_ambisonic_buffer(std::move(planar), rate, N);
    if (b == 0) return fail(w, ES_OUT_OF_MEMORY, format("%s: max_buffers are in use", call));
    *out = b;
    return ES_OK;
  });
}

ES_API ESenum esSourceAmbisonicCallback(ESworld h, ESsource s, ESuint order, ESambisoniccallback cb, void* user) {
  return with_source(h, s, "esSourceAmbisonicCallback", [&](World& w, SourceParams& sp, std::size_t slot) -> ESenum {
    if (cb && (order < 1 || order > ES_MAX_AMBISONIC_ORDER))
      return fail(w, ES_INVALID_VALUE,
                  format("esSourceAmbisonicCallback: order %u (1 to %d)", order, ES_MAX_AMBISONIC_ORDER));
    if (cb) w.prepare_bed(slot, static_cast<int>(order));  // may design the decoder: throws, nothing changed
    sp.field_callback = cb;
    sp.callback = nullptr;
    sp.user = cb ? user : nullptr;
    sp.order = cb ? static_cast<int>(order) : 0;
    sp.buffer = 0;
    sp.data = nullptr;
    sp.frames = 0;
    w.changed();
    return ES_OK;
  });
}

// ---- the table ----

namespace {
constexpr ESproctable kTable = {
    ES_ABI_VERSION, sizeof(ESproctable),
    esGetErrorString, esWorldParamsDefault, esCreateWorld, esDestroyWorld, esSetControlThread, esGetErrorMessage,
    esWorldi, esGetWorldi, esDopplerFactor, esSpeedOfSound, esCommit,
    esListenerf, esListener3f, esListenerfv, esGetListenerfv,
    esCreateBuffer, esDeleteBuffer,
    esCreateSource, esDeleteSource, esSourcef, esSource3f, esSourcefv, esSourcei,
    esGetSourcef, esGetSourcefv, esGetSourcei, esSourceCallback,
    esSourcePlay, esSourcePause, esSourceStop, esSourceRewind,
    esReverbPreset, esReverbf, esReverbi, esGetReverbf,
    esAttachTracker, esRecenter, esGetHeadPose, esSetHeadPose,
    esRender,
    esGetTrackerState,  // ABI 1.1
    esWorldHrtf,        // ABI 1.2
    esGetTrackerImage,  // ABI 1.3
    esAttachTrackerEx,  // ABI 1.4
    esCreateAmbisonicBuffer, esSourceAmbisonicCallback,  // ABI 1.5
};
}  // namespace

ES_API const ESproctable* esGetProcTable(ESuint abi_major) {
  return abi_major == ES_ABI_VERSION_MAJOR ? &kTable : nullptr;
}

}  // extern "C"
