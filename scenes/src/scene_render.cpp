// Offline rendering through the plugin's C API (earshot/earshot.h): the same
// path a game engine or the live demo takes. One world per render, in
// deferred commit mode: each block's listener pose and source positions are
// set, committed together and heard from the block esRender() then renders.
// The scene's sounds are callback sources (SignalSource::generate runs inside
// esRender). The world is made as `earshot render` always rendered: the
// propagation delay (distance / speed of sound, so motion makes the Doppler
// shift), the room's reverb on the send bus returning into the next block.
#include "earshot/scenes/scene_render.hpp"

#include <sndfile.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "earshot/audio/renderer.hpp"
#include "earshot/earshot.h"
#include "earshot/errors.hpp"
#include "earshot/scenes/pose_track.hpp"
#include "earshot/scenes/signal_source.hpp"

namespace earshot::scenes {
namespace {
struct SndfileClose {
  void operator()(SNDFILE* f) const { sf_close(f); }
};
double db(double x) { return std::pow(10.0, x / 20.0); }
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr std::size_t kMaxSources = 256;  // ESworldparams::max_sources

/// Bad input (a value, a file) is an InputError (exit code 2); anything else
/// the plugin refuses is a bug here, a runtime_error.
[[noreturn]] void raise(ESenum e, const std::string& message) {
  if (e == ES_INVALID_VALUE || e == ES_HRTF_ERROR) throw InputError(message);
  throw std::runtime_error(message + " (" + esGetErrorString(e) + ")");
}

/// A plugin world for one render; destroyed on every way out.
class World {
 public:
  explicit World(const ESworldparams& p) {
    // esGetErrorMessage(0): why this thread's esCreateWorld failed, e.g.
    // "x.sofa: not a SOFA file" (the message the command always printed).
    if (const ESenum e = esCreateWorld(&p, &w_); e != ES_OK) raise(e, esGetErrorMessage(0));
  }
  ~World() { (void)esDestroyWorld(w_); }
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  [[nodiscard]] ESworld id() const { return w_; }
  /// Throws when `e` is not ES_OK: "origin: field 'f': <the plugin's message>".
  void check(ESenum e, std::string_view origin, std::string_view field) const {
    if (e != ES_OK) fail(e, origin, field);
  }
  [[noreturn]] void fail(ESenum e, std::string_view origin, std::string_view field) const {
    raise(e, InputError::at(origin, 0, field, esGetErrorMessage(w_)).what());
  }

 private:
  ESworld w_ = 0;
};

ESenum distance_model(audio::DistanceModel m) {
  using M = audio::DistanceModel;
  switch (m) {
    case M::none: return ES_NONE;
    case M::inverse: return ES_INVERSE_DISTANCE;
    case M::inverse_clamped: return ES_INVERSE_DISTANCE_CLAMPED;
    case M::linear: return ES_LINEAR_DISTANCE;
    case M::linear_clamped: return ES_LINEAR_DISTANCE_CLAMPED;
    case M::exponent: return ES_EXPONENT_DISTANCE;
    case M::exponent_clamped: return ES_EXPONENT_DISTANCE_CLAMPED;
  }
  return ES_INVERSE_DISTANCE_CLAMPED;
}

/// The callback source: the scene's generator fills the block on the audio side.
void pull(void* user, float* out, ESuint frames) {
  static_cast<SignalSource*>(user)->generate(std::span<float>(out, frames));
}

void set_listener(const World& w, const audio::ListenerState& l, std::string_view origin, double t) {
  const float pos[3] = {float(l.position[0]), float(l.position[1]), float(l.position[2])};
  const float quat[4] = {float(l.orientation[0]), float(l.orientation[1]), float(l.orientation[2]),
                         float(l.orientation[3])};
  ESenum e = esListenerfv(w.id(), ES_POSITION, pos);
  if (e == ES_OK) e = esListenerfv(w.id(), ES_ORIENTATION_QUAT, quat);
  if (e != ES_OK) w.fail(e, origin, "listener at t = " + std::to_string(t) + " s");
}
}  // namespace

RenderStats render_scene(const Scene& scene, const RenderOptions& opt) {
  // The world runs at whole Hz, as the WAV header says.
  const double rate = std::round(opt.sample_rate.value_or(scene.sample_rate));
  const double duration = opt.duration_s.value_or(scene.duration_s);
  if (opt.block == 0 || opt.block > 8192) throw InputError::at("--block", 0, "", "must be 1 to 8192 frames");
  if (!(rate >= 8000 && rate <= 192000)) throw InputError::at("--rate", 0, "", "must be 8000 to 192000 Hz");
  const std::string origin = scene.origin.empty() ? "scene" : scene.origin;
  if (scene.sources.size() > kMaxSources)
    throw InputError::at(origin, 0, "sources",
                         std::to_string(scene.sources.size()) + " sources; a world renders at most " +
                             std::to_string(kMaxSources));
  std::optional<PoseTrack> track;
  const auto track_path = opt.pose_track ? opt.pose_track : scene.pose_track;
  if (track_path) track = PoseTrack::load(*track_path);

  ESworldparams p;
  esWorldParamsDefault(&p);
  p.sample_rate = static_cast<ESuint>(rate);
  p.block_size = static_cast<ESuint>(opt.block);
  p.max_sources = static_cast<ESuint>(std::max<std::size_t>(1, scene.sources.size()));
  p.max_buffers = 1;
  p.doppler_factor = static_cast<ESfloat>(scene.doppler_factor);
  p.speed_of_sound = static_cast<ESfloat>(scene.speed_of_sound);
  p.propagation_delay = ES_TRUE;  // motion makes the Doppler shift, as the renderer does it
  p.late_reverb = scene.reverb == "schroeder" ? ES_REVERB_SCHROEDER : ES_REVERB_FDN;
  p.head_radius_m = static_cast<ESfloat>(scene.listener.head_radius_m.value_or(0.0));  // 0: measured ITD
  const std::string hrtf = opt.hrtf.string();
  p.hrtf_path = hrtf.empty() ? nullptr : hrtf.c_str();
  // The generators outlive the world whose callbacks point into them.
  std::vector<SignalSource> signals;
  signals.reserve(scene.sources.size());  // no reallocation: the callbacks keep pointers
  const World world(p);
  const ESworld w = world.id();
  // Each block's changes land together, at that block.
  world.check(esWorldi(w, ES_COMMIT_MODE, ES_DEFERRED), origin, "");

  // The room: the renderer's send bus through the reverb, back into the next block's mix.
  if (scene.room != "none") {
    world.check(esReverbPreset(w, scene.room.c_str()), origin, "room");
    world.check(esReverbi(w, ES_REVERB_ENABLED, ES_TRUE), origin, "room");
  }

  std::vector<ESsource> ids;
  for (std::size_t i = 0; i < scene.sources.size(); ++i) {
    const SceneSource& s = scene.sources[i];
    const std::string f = "sources[" + std::to_string(i) + "]";
    signals.emplace_back(s.signal, rate);
    ESsource id = 0;
    world.check(esCreateSource(w, &id), origin, f);
    ids.push_back(id);
    const auto set = [&](ESenum param, double v, const char* name) {
      world.check(esSourcef(w, id, param, static_cast<ESfloat>(v)), origin, f + "." + name);
    };
    world.check(esSource3f(w, id, ES_POSITION, float(s.position[0]), float(s.position[1]), float(s.position[2])),
                origin, f + ".position");
    set(ES_GAIN, db(s.gain_db), "gain_db");
    world.check(esSourcei(w, id, ES_DISTANCE_MODEL, distance_model(s.distance.model)), origin, f + ".distance_model");
    set(ES_REFERENCE_DISTANCE, s.distance.reference_distance, "reference_distance");
    set(ES_ROLLOFF_FACTOR, s.distance.rolloff, "rolloff");
    set(ES_MAX_DISTANCE, s.distance.max_distance, "max_distance");
    set(ES_REVERB_SEND, s.reverb_send_db <= -120 ? 0.0 : db(s.reverb_send_db), "reverb_send_db");
    set(ES_AIR_ABSORPTION_FACTOR, s.air_absorption, "air_absorption");
    world.check(esSourceCallback(w, id, pull, &signals.back()), origin, f + ".signal");
    world.check(esSourcePlay(w, id), origin, f);
  }
  const std::string track_origin = track_path ? track_path->string() : origin;
  if (!track) {
    audio::ListenerState fixed;
    fixed.position = scene.listener.position;
    fixed.orientation = audio::quat_from_ypr(scene.listener.yaw_deg * kDeg, scene.listener.pitch_deg * kDeg,
                                             scene.listener.roll_deg * kDeg);
    set_listener(world, fixed, origin, 0.0);
  }

  SF_INFO info{};
  info.samplerate = static_cast<int>(rate);
  info.channels = 2;
  info.format = SF_FORMAT_WAV | (opt.format == WavFormat::float32 ? SF_FORMAT_FLOAT : SF_FORMAT_PCM_24);
  std::unique_ptr<SNDFILE, SndfileClose> out(sf_open(opt.out.c_str(), SFM_WRITE, &info));
  if (!out) throw InputError::at(opt.out.string(), 0, "", std::string("cannot write: ") + sf_strerror(nullptr));
  sf_command(out.get(), SFC_SET_ADD_PEAK_CHUNK, nullptr, SF_FALSE);  // it carries a timestamp

  RenderStats stats;
  const auto total = static_cast<std::size_t>(std::llround(duration * rate));
  std::vector<float> l(opt.block), r(opt.block), inter(2 * opt.block);
  std::size_t done = 0, next_report = 0;
  while (done < total) {
    if (opt.stop && opt.stop()) {
      stats.stopped = true;
      break;  // `out` closes below: libsndfile writes the header's final sizes
    }
    const double t = static_cast<double>(done) / rate;
    if (track) set_listener(world, track->at(t), track_origin, t);
    // Moving sources: the path's position at the block's start; the renderer
    // glides the propagation delay across the block, so Doppler follows.
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (scene.sources[i].path) {
        const Point3 pos = source_position(scene.sources[i], t);
        const ESenum e = esSource3f(w, ids[i], ES_POSITION, float(pos[0]), float(pos[1]), float(pos[2]));
        if (e != ES_OK) world.fail(e, origin, "sources[" + std::to_string(i) + "].path");
      }
    world.check(esCommit(w), origin, "");
    // esRender keeps no message (it runs on an audio thread): only a code.
    if (const ESenum e = esRender(w, l.data(), r.data(), static_cast<ESuint>(opt.block)); e != ES_OK)
      throw std::runtime_error(std::string("esRender: ") + esGetErrorString(e));
    const std::size_t n = std::min(opt.block, total - done);
    for (std::size_t i = 0; i < n; ++i) {
      inter[2 * i] = l[i];
      inter[2 * i + 1] = r[i];
      stats.peak = std::max({stats.peak, double(std::abs(l[i])), double(std::abs(r[i]))});
    }
    if (sf_writef_float(out.get(), inter.data(), static_cast<sf_count_t>(n)) != static_cast<sf_count_t>(n))
      throw InputError::at(opt.out.string(), 0, "", std::string("write failed: ") + sf_strerror(out.get()));
    done += n;
    if (opt.progress && done >= next_report) {
      opt.progress(static_cast<double>(done) / static_cast<double>(total));
      next_report = done + total / 100 + 1;
    }
  }
  // Closing writes the header's final sizes: a failure there (a full disk)
  // would leave a WAV that claims no frames.
  if (const int e = sf_close(out.release()); e != 0)
    throw InputError::at(opt.out.string(), 0, "", std::string("write failed: ") + sf_error_number(e));
  stats.frames = done;
  return stats;
}

}  // namespace earshot::scenes
