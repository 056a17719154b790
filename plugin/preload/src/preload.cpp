// libearshot_openal_preload.so: head tracking for unmodified OpenAL programs
// (docs/OPENAL_RUN.md). Loaded with LD_PRELOAD by earshot-openal-run, it
// defines the OpenAL entry points that carry the listener's position and
// orientation, so the program's calls land here first:
//
//   program sets   P (orientation), p (position)     -- stored per context
//   OpenAL gets    P x H,  p + P h                   -- H, h: the tracked head
//   program reads  P, p (alGetListener*)             -- what it set, not the composed pose
//
// and forwards them to OpenAL Soft's own functions (dlsym RTLD_NEXT). Frames:
// OpenAL's (+x right, +y up, -z ahead, metres); the head pose is relative to
// the program's listener, in the listener's own frame (earshot/geometry.hpp).
//
// A tracker (the spec in EARSHOT_OPENAL_TRACKER) starts on the first
// alcMakeContextCurrent/alcSetThreadContext; on every pose it publishes, its
// thread re-applies the composed listener to every context the program made
// current, so the sound follows the head while the program leaves its
// listener alone. Stereo sources, which OpenAL Soft plays head-locked, get
// AL_STEREO_ANGLES turned against the head's yaw, so their two channels stay
// as speakers in the room (EARSHOT_OPENAL_PLACE=stereo, the default); with
// "all", mono sources that play at the listener (music players) are also
// moved 1 m ahead into the room; "none" leaves every source alone.
//
// Threads: OpenAL Soft is thread-safe; the shim's state (the contexts the
// program made current, its listener in each, its stereo sources) is behind
// one mutex, taken by the program's listener/context/source calls and by the
// tracker thread while it applies a pose. alcDestroyContext and
// alcCloseDevice forget a context under that mutex before OpenAL frees it, so
// the tracker thread never touches a destroyed context. The tracker thread
// reaches each context through alcSetThreadContext (ALC_EXT_thread_local_context,
// in every OpenAL Soft), so it also serves contexts that are current only on
// one program thread; without that extension it serves the process-wide
// current context only.
//
// Global state: the one Shim instance (function-local static, built on the
// first OpenAL call, destroyed at exit: tracker stopped and joined first) and
// the immutable table of OpenAL Soft's real functions.
#include <AL/al.h>
#include <AL/alc.h>
#include <AL/alext.h>
#include <dlfcn.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <numbers>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "earshot/geometry.hpp"
#include "earshot/head/head_reader.hpp"
#include "earshot/head/tracked_head.hpp"
#include "earshot/pose_slot.hpp"
#include "openal_latency.hpp"
#include "shim_listener.hpp"

#define EARSHOT_EXPORT extern "C" __attribute__((visibility("default")))

namespace {

using earshot::Quat;
using earshot::Vec3;

constexpr const char* kPrefix = "earshot-openal-run: ";

template <class F>
F next_symbol(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

// OpenAL Soft's own entry points (the next definitions after this library).
// Resolved once and never written again.
struct Real {
  LPALLISTENER3F listener3f = next_symbol<LPALLISTENER3F>("alListener3f");
  LPALLISTENERFV listenerfv = next_symbol<LPALLISTENERFV>("alListenerfv");
  LPALLISTENER3I listener3i = next_symbol<LPALLISTENER3I>("alListener3i");
  LPALLISTENERIV listeneriv = next_symbol<LPALLISTENERIV>("alListeneriv");
  LPALGETLISTENER3F get_listener3f = next_symbol<LPALGETLISTENER3F>("alGetListener3f");
  LPALGETLISTENERFV get_listenerfv = next_symbol<LPALGETLISTENERFV>("alGetListenerfv");
  LPALGETLISTENER3I get_listener3i = next_symbol<LPALGETLISTENER3I>("alGetListener3i");
  LPALGETLISTENERIV get_listeneriv = next_symbol<LPALGETLISTENERIV>("alGetListeneriv");
  LPALSOURCEI sourcei = next_symbol<LPALSOURCEI>("alSourcei");
  LPALSOURCEFV sourcefv = next_symbol<LPALSOURCEFV>("alSourcefv");
  LPALSOURCE3F source3f = next_symbol<LPALSOURCE3F>("alSource3f");
  LPALGETSOURCEI get_sourcei = next_symbol<LPALGETSOURCEI>("alGetSourcei");
  LPALGETSOURCEFV get_sourcefv = next_symbol<LPALGETSOURCEFV>("alGetSourcefv");
  LPALSOURCEPLAY source_play = next_symbol<LPALSOURCEPLAY>("alSourcePlay");
  LPALSOURCEPLAYV source_playv = next_symbol<LPALSOURCEPLAYV>("alSourcePlayv");
  LPALISEXTENSIONPRESENT is_extension_present = next_symbol<LPALISEXTENSIONPRESENT>("alIsExtensionPresent");
  LPALSOURCEQUEUEBUFFERS source_queue_buffers = next_symbol<LPALSOURCEQUEUEBUFFERS>("alSourceQueueBuffers");
  LPALDELETESOURCES delete_sources = next_symbol<LPALDELETESOURCES>("alDeleteSources");
  LPALGETBUFFERI get_bufferi = next_symbol<LPALGETBUFFERI>("alGetBufferi");
  LPALISBUFFER is_buffer = next_symbol<LPALISBUFFER>("alIsBuffer");
  LPALGETPROCADDRESS get_proc_address = next_symbol<LPALGETPROCADDRESS>("alGetProcAddress");
  LPALCGETPROCADDRESS alc_get_proc_address = next_symbol<LPALCGETPROCADDRESS>("alcGetProcAddress");
  LPALCMAKECONTEXTCURRENT make_context_current = next_symbol<LPALCMAKECONTEXTCURRENT>("alcMakeContextCurrent");
  LPALCDESTROYCONTEXT destroy_context = next_symbol<LPALCDESTROYCONTEXT>("alcDestroyContext");
  LPALCCLOSEDEVICE close_device = next_symbol<LPALCCLOSEDEVICE>("alcCloseDevice");
  LPALCGETCURRENTCONTEXT get_current_context = next_symbol<LPALCGETCURRENTCONTEXT>("alcGetCurrentContext");
  LPALCGETCONTEXTSDEVICE get_contexts_device = next_symbol<LPALCGETCONTEXTSDEVICE>("alcGetContextsDevice");
  PFNALCSETTHREADCONTEXTPROC set_thread_context = next_symbol<PFNALCSETTHREADCONTEXTPROC>("alcSetThreadContext");
};

const Real& real() {
  static const Real r;
  return r;
}

bool verbose() {
  static const bool v = [] {
    const char* e = std::getenv("EARSHOT_OPENAL_RUN_VERBOSE");
    return e && *e && std::string_view(e) != "0";
  }();
  return v;
}

// The listener as the program set it in one context, and its stereo sources.
struct ContextState {
  float position[3] = {0, 0, 0};
  float orientation[6] = {0, 0, -1, 0, 1, 0};  // "at" then "up", OpenAL's default
  Quat rotation = earshot::kIdentityQuat;       // of `orientation`; identity if degenerate
  bool composable = true;                       // false: at/up degenerate, forwarded as given
  double lead_s = 0.0;                          // its device's latency: how far ahead the head is predicted
  std::unordered_set<ALuint> stereo_sources;
  std::unordered_set<ALuint> mono_sources;   // have a mono buffer (candidates for Place::all)
  std::unordered_set<ALuint> placed_mono;    // moved from the listener to 1 m ahead
};

// What the shim does to sources OpenAL Soft would play head-locked.
enum class Place {
  none,    // nothing: only the listener turns
  stereo,  // stereo sources: speakers at +-30 degrees in the room
  all,     // and mono sources at the listener: 1 m ahead in the room
};

class Shim {
 public:
  static Shim& get() {
    static Shim s;
    return s;
  }
  Shim(const Shim&) = delete;
  Shim& operator=(const Shim&) = delete;
  ~Shim() { tracker_.reset(); }  // joins the tracker thread (not under mu_: its callback takes it)

  // A context became current (process-wide or on one thread).
  void made_current(ALCcontext* ctx) {
    if (!ctx) return;
    start_tracker_once();
    std::lock_guard lock(mu_);
    if (contexts_.try_emplace(ctx).second && verbose())
      std::fprintf(stderr, "%scontext %p made current\n", kPrefix, static_cast<void*>(ctx));
  }

  void forget_context(ALCcontext* ctx) {
    std::lock_guard lock(mu_);
    contexts_.erase(ctx);
  }

  void forget_device(ALCdevice* dev) {
    std::lock_guard lock(mu_);
    std::erase_if(contexts_, [&](const auto& kv) { return real().get_contexts_device(kv.first) == dev; });
  }

  // The program sets its listener's position (3 values) on its current context.
  void set_position(const float* p) {
    std::lock_guard lock(mu_);
    ContextState* s = current_state();
    if (!s || !std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      real().listenerfv(AL_POSITION, p);  // OpenAL reports the error
      return;
    }
    std::memcpy(s->position, p, sizeof s->position);
    apply(*s);
  }

  void set_orientation(const float* o) {
    std::lock_guard lock(mu_);
    ContextState* s = current_state();
    bool finite = true;
    for (int i = 0; i < 6; ++i) finite = finite && std::isfinite(o[i]);
    if (!s || !finite) {
      real().listenerfv(AL_ORIENTATION, o);
      return;
    }
    std::memcpy(s->orientation, o, sizeof s->orientation);
    const auto q = earshot::quat_from_at_up(Vec3{o[0], o[1], o[2]}, Vec3{o[3], o[4], o[5]});
    s->composable = q.has_value();
    s->rotation = q.value_or(earshot::kIdentityQuat);
    apply(*s);
  }

  // What the program set (false: no current context, let OpenAL answer).
  bool get_position(float* out) {
    std::lock_guard lock(mu_);
    const ContextState* s = current_state();
    if (!s) return false;
    std::memcpy(out, s->position, sizeof s->position);
    return true;
  }

  bool get_orientation(float* out) {
    std::lock_guard lock(mu_);
    const ContextState* s = current_state();
    if (!s) return false;
    std::memcpy(out, s->orientation, sizeof s->orientation);
    return true;
  }

  // A buffer was attached to or queued on `source` in the current context.
  void buffer_attached(ALuint source, ALuint buffer) {
    if (place_ == Place::none || buffer == 0 || !real().is_buffer(buffer)) return;
    ALint channels = 0;
    real().get_bufferi(buffer, AL_CHANNELS, &channels);
    std::lock_guard lock(mu_);
    ContextState* s = current_state();
    if (!s) return;
    if (channels == 2) {
      if (s->stereo_sources.insert(source).second && verbose())
        std::fprintf(stderr, "%sstereo source %u placed as two speakers at +-30 degrees\n", kPrefix, source);
      apply_stereo(source, heard_head(*s));
      s->mono_sources.erase(source);
    } else if (channels == 1) {
      s->stereo_sources.erase(source);
      s->mono_sources.insert(source);
    }
  }

  // Place::all: a mono source about to play at the listener (relative at
  // the origin, or at the program's listener position) is moved 1 m ahead
  // of the program's listener, where head turns are heard.
  void source_playing(ALuint source) {
    if (place_ != Place::all) return;
    std::lock_guard lock(mu_);
    ContextState* s = current_state();
    if (!s || !s->mono_sources.contains(source) || s->placed_mono.contains(source)) return;
    ALint relative = AL_FALSE, spatialize = AL_AUTO_SOFT;
    float pos[3] = {0, 0, 0};
    real().get_sourcei(source, AL_SOURCE_RELATIVE, &relative);
    real().get_sourcefv(source, AL_POSITION, pos);
    if (real().is_extension_present("AL_SOFT_source_spatialize"))
      real().get_sourcei(source, AL_SOURCE_SPATIALIZE_SOFT, &spatialize);
    if (spatialize == AL_FALSE) return;
    const float* origin = relative ? nullptr : s->position;
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
      const double d = pos[i] - (origin ? origin[i] : 0.0f);
      d2 += d * d;
    }
    if (d2 > 1e-6) return;
    s->placed_mono.insert(source);
    if (verbose()) std::fprintf(stderr, "%smono source %u at the listener placed 1 m ahead\n", kPrefix, source);
    apply_mono(source, heard_head(*s));
  }

  // The program placed the source itself: it is the program's again.
  void source_moved(ALuint source) {
    std::lock_guard lock(mu_);
    if (ContextState* s = current_state()) s->placed_mono.erase(source);
  }

  void sources_deleted(ALsizei n, const ALuint* sources) {
    std::lock_guard lock(mu_);
    ContextState* s = current_state();
    if (!s || n <= 0 || !sources) return;
    for (ALsizei i = 0; i < n; ++i) {
      s->stereo_sources.erase(sources[i]);
      s->mono_sources.erase(sources[i]);
      s->placed_mono.erase(sources[i]);
    }
  }

 private:
  Shim() {
    const char* p = std::getenv("EARSHOT_OPENAL_PLACE");
    const std::string_view place = p ? p : "stereo";
    if (place == "none") {
      place_ = Place::none;
    } else if (place == "all") {
      place_ = Place::all;
    } else if (place != "stereo") {
      std::fprintf(stderr, "%sEARSHOT_OPENAL_PLACE=\"%s\" is not none, stereo or all; using stereo\n", kPrefix, p);
    }
  }

  // The context this thread's OpenAL calls go to (thread-local one first:
  // alcGetCurrentContext answers that way), registered if new. Under mu_.
  ContextState* current_state() {
    ALCcontext* ctx = real().get_current_context();
    if (!ctx) return nullptr;
    auto [it, fresh] = contexts_.try_emplace(ctx);
    if (fresh) it->second.lead_s = earshot::openal::output_latency_s(real().get_contexts_device(ctx));
    return &it->second;
  }

  void start_tracker_once() {
    std::call_once(tracker_once_, [this] {
      const char* e = std::getenv("EARSHOT_OPENAL_TRACKER");
      const std::string spec = e && *e ? e : "wiimote";
      try {
        if (const char* r = std::getenv("EARSHOT_OPENAL_RECENTER_AFTER"); r && *r)
          recenter_after_s_ = std::strtod(r, nullptr);
        started_ = std::chrono::steady_clock::now();
        // Under mu_: the first pose's callback waits until tracker_ is set.
        std::lock_guard lock(mu_);
        tracker_ = std::make_unique<earshot::head::TrackedHead>(
            spec, slot_, earshot::tracker::TrackerOptions{}, "EARSHOT_OPENAL_TRACKER",
            [this](const earshot::HeadPose& pose) { on_pose(pose); });
        if (verbose()) std::fprintf(stderr, "%stracker \"%s\" started\n", kPrefix, spec.c_str());
      } catch (const std::exception& ex) {
        std::fprintf(stderr, "%scannot start the tracker \"%s\": %s; playing on without head tracking\n", kPrefix,
                     spec.c_str(), ex.what());
      }
    });
  }

  // The tracker thread, after each published pose.
  void on_pose(const earshot::HeadPose& pose) {
    std::lock_guard lock(mu_);
    if (recenter_after_s_ > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count() >= recenter_after_s_) {
      recenter_after_s_ = 0;  // once
      if (tracker_) tracker_->recenter();
    }
    tracked_ = pose;
    if (real().set_thread_context) {
      for (auto& [ctx, state] : contexts_) {
        if (!real().set_thread_context(ctx)) continue;
        apply(state);
      }
      real().set_thread_context(nullptr);
    } else if (ALCcontext* ctx = real().get_current_context()) {
      if (auto it = contexts_.find(ctx); it != contexts_.end()) apply(it->second);
    }
  }

  // The tracked head as the next mix of the state's context will hear it. Under mu_.
  [[nodiscard]] earshot::HeadPose heard_head(const ContextState& s) const {
    return earshot::head::heard(tracked_, {.predict = true, .lead_s = s.lead_s}, earshot::head::steady_now_s());
  }

  // The composed listener onto the calling thread's current context (= the
  // state's context). Under mu_.
  void apply(ContextState& s) {
    earshot::HeadPose program;
    program.position = {s.position[0], s.position[1], s.position[2]};
    program.orientation = s.rotation;
    earshot::preload::ShimListener l = earshot::preload::shim_listener(program, tracked_, s.lead_s, earshot::head::steady_now_s());
    if (!s.composable) {
      std::memcpy(l.position, s.position, sizeof l.position);
      std::memcpy(l.orientation, s.orientation, sizeof l.orientation);
    }
    real().listenerfv(AL_POSITION, l.position);
    real().listenerfv(AL_ORIENTATION, l.orientation);
    for (ALuint src : s.stereo_sources) apply_stereo(src, l.head);
    for (ALuint src : s.placed_mono) apply_mono(src, l.head);
  }

  // 1 m ahead of the program's listener, as seen from the head (relative to
  // the effective listener P H at p + P h: H^-1 ((0, 0, -1) - h)). Under mu_.
  static void apply_mono(ALuint source, const earshot::HeadPose& head) {
    const Vec3 v = earshot::rotate_inverse(
        head.orientation, Vec3{-head.position[0], -head.position[1], -1.0 - head.position[2]});
    real().sourcei(source, AL_SOURCE_RELATIVE, AL_TRUE);
    real().source3f(source, AL_POSITION, static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
  }

  // AL_STEREO_ANGLES are relative to the head (anticlockwise, radians): the
  // room's +-30 degree speakers sit at +-30 minus the head's yaw. Under mu_.
  static void apply_stereo(ALuint source, const earshot::HeadPose& head) {
    const double yaw = earshot::ypr_from_quat(head.orientation).yaw;
    const float angles[2] = {static_cast<float>(std::numbers::pi / 6 - yaw), static_cast<float>(-std::numbers::pi / 6 - yaw)};
    real().sourcefv(source, AL_STEREO_ANGLES, angles);
  }

  std::mutex mu_;  // everything below but tracker_ and the once flag
  std::unordered_map<ALCcontext*, ContextState> contexts_;
  earshot::HeadPose tracked_;  // the newest published head pose
  Place place_ = Place::stereo;  // set in the constructor only
  double recenter_after_s_ = 0;
  std::chrono::steady_clock::time_point started_{};
  std::once_flag tracker_once_;
  earshot::PoseSlot slot_;
  std::unique_ptr<earshot::head::TrackedHead> tracker_;  // set once under mu_; reset unlocked at exit
};

// This library's own handle, for dlopen("libopenal.so...") (below).
void* self_handle() {
  Dl_info info{};
  if (!dladdr(reinterpret_cast<void*>(&self_handle), &info) || !info.dli_fname) return nullptr;
  return dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD);
}

bool names_openal(const char* file) {
  if (!file) return false;
  const char* base = std::strrchr(file, '/');
  base = base ? base + 1 : file;
  return std::strncmp(base, "libopenal.so", 12) == 0;
}

void* our_proc(std::string_view name);

}  // namespace

// ---- The interposed entry points ------------------------------------------

EARSHOT_EXPORT void alListener3f(ALenum param, ALfloat a, ALfloat b, ALfloat c) {
  if (param != AL_POSITION) return real().listener3f(param, a, b, c);
  const float p[3] = {a, b, c};
  Shim::get().set_position(p);
}

EARSHOT_EXPORT void alListenerfv(ALenum param, const ALfloat* values) {
  if (!values || (param != AL_POSITION && param != AL_ORIENTATION)) return real().listenerfv(param, values);
  if (param == AL_POSITION)
    Shim::get().set_position(values);
  else
    Shim::get().set_orientation(values);
}

EARSHOT_EXPORT void alListener3i(ALenum param, ALint a, ALint b, ALint c) {
  if (param != AL_POSITION) return real().listener3i(param, a, b, c);
  const float p[3] = {static_cast<float>(a), static_cast<float>(b), static_cast<float>(c)};
  Shim::get().set_position(p);
}

EARSHOT_EXPORT void alListeneriv(ALenum param, const ALint* values) {
  if (!values || (param != AL_POSITION && param != AL_ORIENTATION)) return real().listeneriv(param, values);
  float f[6];
  const int n = param == AL_POSITION ? 3 : 6;
  for (int i = 0; i < n; ++i) f[i] = static_cast<float>(values[i]);
  alListenerfv(param, f);
}

EARSHOT_EXPORT void alGetListener3f(ALenum param, ALfloat* a, ALfloat* b, ALfloat* c) {
  float p[3];
  if (param != AL_POSITION || !a || !b || !c || !Shim::get().get_position(p))
    return real().get_listener3f(param, a, b, c);
  *a = p[0], *b = p[1], *c = p[2];
}

EARSHOT_EXPORT void alGetListenerfv(ALenum param, ALfloat* values) {
  if (values && param == AL_POSITION && Shim::get().get_position(values)) return;
  if (values && param == AL_ORIENTATION && Shim::get().get_orientation(values)) return;
  real().get_listenerfv(param, values);
}

EARSHOT_EXPORT void alGetListener3i(ALenum param, ALint* a, ALint* b, ALint* c) {
  float p[3];
  if (param != AL_POSITION || !a || !b || !c || !Shim::get().get_position(p))
    return real().get_listener3i(param, a, b, c);
  *a = static_cast<ALint>(p[0]), *b = static_cast<ALint>(p[1]), *c = static_cast<ALint>(p[2]);
}

EARSHOT_EXPORT void alGetListeneriv(ALenum param, ALint* values) {
  float f[6];
  const int n = param == AL_POSITION ? 3 : 6;
  const bool ours = values && ((param == AL_POSITION && Shim::get().get_position(f)) ||
                               (param == AL_ORIENTATION && Shim::get().get_orientation(f)));
  if (!ours) return real().get_listeneriv(param, values);
  for (int i = 0; i < n; ++i) values[i] = static_cast<ALint>(f[i]);
}

EARSHOT_EXPORT void alSourcei(ALuint source, ALenum param, ALint value) {
  real().sourcei(source, param, value);
  if (param == AL_BUFFER) Shim::get().buffer_attached(source, static_cast<ALuint>(value));
  if (param == AL_SOURCE_RELATIVE) Shim::get().source_moved(source);
}

EARSHOT_EXPORT void alSource3f(ALuint source, ALenum param, ALfloat a, ALfloat b, ALfloat c) {
  real().source3f(source, param, a, b, c);
  if (param == AL_POSITION) Shim::get().source_moved(source);
}

EARSHOT_EXPORT void alSourcefv(ALuint source, ALenum param, const ALfloat* values) {
  real().sourcefv(source, param, values);
  if (param == AL_POSITION) Shim::get().source_moved(source);
}

EARSHOT_EXPORT void alSourcePlay(ALuint source) {
  Shim::get().source_playing(source);
  real().source_play(source);
}

EARSHOT_EXPORT void alSourcePlayv(ALsizei n, const ALuint* sources) {
  for (ALsizei i = 0; sources && i < n; ++i) Shim::get().source_playing(sources[i]);
  real().source_playv(n, sources);
}

EARSHOT_EXPORT void alSourceQueueBuffers(ALuint source, ALsizei n, const ALuint* buffers) {
  real().source_queue_buffers(source, n, buffers);
  if (n > 0 && buffers) Shim::get().buffer_attached(source, buffers[n - 1]);
}

EARSHOT_EXPORT void alDeleteSources(ALsizei n, const ALuint* sources) {
  Shim::get().sources_deleted(n, sources);
  real().delete_sources(n, sources);
}

EARSHOT_EXPORT ALCboolean alcMakeContextCurrent(ALCcontext* ctx) {
  const ALCboolean ok = real().make_context_current(ctx);
  if (ok) Shim::get().made_current(ctx);
  return ok;
}

EARSHOT_EXPORT ALCboolean alcSetThreadContext(ALCcontext* ctx) {
  if (!real().set_thread_context) return ALC_FALSE;
  const ALCboolean ok = real().set_thread_context(ctx);
  if (ok) Shim::get().made_current(ctx);
  return ok;
}

EARSHOT_EXPORT void alcDestroyContext(ALCcontext* ctx) {
  Shim::get().forget_context(ctx);  // before OpenAL frees it
  real().destroy_context(ctx);
}

EARSHOT_EXPORT ALCboolean alcCloseDevice(ALCdevice* dev) {
  Shim::get().forget_device(dev);  // OpenAL Soft destroys a closed device's contexts
  return real().close_device(dev);
}

// Programs that look the functions up get ours too.
EARSHOT_EXPORT void* alGetProcAddress(const ALchar* name) {
  if (void* f = name ? our_proc(name) : nullptr) return f;
  return real().get_proc_address(name);
}

EARSHOT_EXPORT void* alcGetProcAddress(ALCdevice* dev, const ALCchar* name) {
  if (void* f = name ? our_proc(name) : nullptr) return f;
  return real().alc_get_proc_address(dev, name);
}

// Bindings that dlopen OpenAL and look its functions up with dlsym (Python's
// ctypes: pyglet) would bypass LD_PRELOAD: they get this library's handle
// instead, whose lookups find the functions above first and everything else
// in libopenal, which this library links. Every other name is dlopen's.
EARSHOT_EXPORT void* dlopen(const char* file, int mode) {
  static const auto next = next_symbol<void* (*)(const char*, int)>("dlopen");
  void* handle = next(file, mode);
  if (handle && names_openal(file)) {
    if (void* self = self_handle()) {
      if (verbose()) std::fprintf(stderr, "%sdlopen(\"%s\") answered with the shim\n", kPrefix, file);
      return self;  // the real handle stays open: libopenal remains loaded
    }
  }
  return handle;
}

namespace {
void* our_proc(std::string_view name) {
  struct Entry {
    std::string_view name;
    void* fn;
  };
  static const Entry table[] = {
      {"alListener3f", reinterpret_cast<void*>(&alListener3f)},
      {"alListenerfv", reinterpret_cast<void*>(&alListenerfv)},
      {"alListener3i", reinterpret_cast<void*>(&alListener3i)},
      {"alListeneriv", reinterpret_cast<void*>(&alListeneriv)},
      {"alGetListener3f", reinterpret_cast<void*>(&alGetListener3f)},
      {"alGetListenerfv", reinterpret_cast<void*>(&alGetListenerfv)},
      {"alGetListener3i", reinterpret_cast<void*>(&alGetListener3i)},
      {"alGetListeneriv", reinterpret_cast<void*>(&alGetListeneriv)},
      {"alSourcei", reinterpret_cast<void*>(&alSourcei)},
      {"alSource3f", reinterpret_cast<void*>(&alSource3f)},
      {"alSourcefv", reinterpret_cast<void*>(&alSourcefv)},
      {"alSourcePlay", reinterpret_cast<void*>(&alSourcePlay)},
      {"alSourcePlayv", reinterpret_cast<void*>(&alSourcePlayv)},
      {"alSourceQueueBuffers", reinterpret_cast<void*>(&alSourceQueueBuffers)},
      {"alDeleteSources", reinterpret_cast<void*>(&alDeleteSources)},
      {"alcMakeContextCurrent", reinterpret_cast<void*>(&alcMakeContextCurrent)},
      {"alcSetThreadContext", reinterpret_cast<void*>(&alcSetThreadContext)},
      {"alcDestroyContext", reinterpret_cast<void*>(&alcDestroyContext)},
      {"alcCloseDevice", reinterpret_cast<void*>(&alcCloseDevice)},
  };
  for (const Entry& e : table)
    if (e.name == name) return e.fn;
  return nullptr;
}
}  // namespace
