#include "earshot/scenes/scene_render.hpp"

#include <sndfile.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "earshot/audio/renderer.hpp"
#include "earshot/audio/room_reverb.hpp"
#include "earshot/errors.hpp"
#include "earshot/hrtf/hrtf_set.hpp"
#include "earshot/scenes/pose_track.hpp"
#include "earshot/scenes/signal_source.hpp"

namespace earshot::scenes {
namespace {
struct SndfileClose {
  void operator()(SNDFILE* f) const { sf_close(f); }
};
double db(double x) { return std::pow(10.0, x / 20.0); }
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

RenderStats render_scene(const Scene& scene, const RenderOptions& opt) {
  const double rate = opt.sample_rate.value_or(scene.sample_rate);
  const double duration = opt.duration_s.value_or(scene.duration_s);
  if (opt.block == 0 || opt.block > 8192) throw InputError::at("--block", 0, "", "must be 1 to 8192 frames");
  auto set = hrtf::HrtfSet::load(opt.hrtf.empty() ? hrtf::HrtfSet::kDefaultPath : opt.hrtf, rate);
  set.set_parametric_itd(scene.listener.head_radius_m);
  auto hrtf = std::make_shared<const hrtf::HrtfSet>(std::move(set));
  std::optional<PoseTrack> track;
  if (auto p = opt.pose_track ? opt.pose_track : scene.pose_track) track = PoseTrack::load(*p);

  audio::RendererConfig cfg;
  cfg.sample_rate = rate;
  cfg.block = opt.block;
  cfg.max_sources = std::max<std::size_t>(1, scene.sources.size());
  cfg.doppler_factor = scene.doppler_factor;
  cfg.speed_of_sound = scene.speed_of_sound;
  audio::Renderer renderer(hrtf, cfg);
  std::vector<SignalSource> signals;
  std::vector<int> ids;
  std::vector<audio::SourceState> states;
  for (const auto& s : scene.sources) {
    signals.emplace_back(s.signal, rate);
    audio::SourceState st;
    st.position = s.position;
    st.gain = db(s.gain_db);
    st.distance = s.distance;
    st.reverb_send = s.reverb_send_db <= -120 ? 0.0 : db(s.reverb_send_db);
    st.air_absorption = s.air_absorption;
    ids.push_back(renderer.add_source(st));
    states.push_back(st);
  }
  // The room: the renderer's send bus through the reverb, back into the next block's mix.
  std::optional<audio::RoomReverb> room;
  if (scene.room != "none")
    room.emplace(rate, opt.block, audio::room_preset(scene.room), audio::late_reverb_type(scene.reverb));
  audio::ListenerState fixed;
  fixed.position = scene.listener.position;
  fixed.orientation = audio::quat_from_ypr(scene.listener.yaw_deg * kDeg, scene.listener.pitch_deg * kDeg,
                                           scene.listener.roll_deg * kDeg);

  SF_INFO info{};
  info.samplerate = static_cast<int>(std::lround(rate));
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
    const double t = static_cast<double>(done) / rate;
    renderer.set_listener(track ? track->at(t) : fixed);
    // Moving sources: the path's position at the block's start; the renderer
    // glides the propagation delay across the block, so Doppler follows.
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (scene.sources[i].path) {
        states[i].position = source_position(scene.sources[i], t);
        renderer.set_source(ids[i], states[i]);
      }
    for (std::size_t i = 0; i < ids.size(); ++i) signals[i].generate(renderer.source_input(ids[i]));
    renderer.render(l, r);
    if (room) room->process(renderer.reverb_send(), renderer.return_left(), renderer.return_right());
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
  stats.frames = done;
  return stats;
}

}  // namespace earshot::scenes
