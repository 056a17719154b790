// Offline rendering through the plugin's C API (earshot/earshot.h): the same
// path a game engine or the live demo takes. One world per render, in
// deferred commit mode: each block's listener pose and source positions are
// set, committed together and heard from the block esRender() then renders.
// The scene's sounds are callback sources (scene_sources.hpp). The world is
// made as `earshot render` always rendered: the propagation delay (distance /
// speed of sound, so motion makes the Doppler shift), the room's reverb on
// the send bus returning into the next block.
#include "earshot/host/scene_render.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "earshot/earshot.h"
#include "earshot/errors.hpp"
#include "earshot/host/listener.hpp"
#include "earshot/host/scene_sources.hpp"
#include "earshot/host/world_handle.hpp"

namespace earshot::host {
namespace {

constexpr std::size_t kMaxSources = 256;  // ESworldparams::max_sources

ESworldparams world_params(const scenes::Scene& scene, double rate, std::size_t block, const std::string& hrtf) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  p.sample_rate = static_cast<ESuint>(rate);
  p.block_size = static_cast<ESuint>(block);
  p.max_sources = static_cast<ESuint>(std::max<std::size_t>(1, scene.sources.size() + scene.beds.size()));
  p.max_buffers = 1;
  p.doppler_factor = static_cast<ESfloat>(scene.doppler_factor);
  p.speed_of_sound = static_cast<ESfloat>(scene.speed_of_sound);
  p.propagation_delay = ES_TRUE;  // motion makes the Doppler shift, as the renderer does it
  p.late_reverb = scene.reverb == "schroeder" ? ES_REVERB_SCHROEDER : ES_REVERB_FDN;
  p.head_radius_m = static_cast<ESfloat>(scene.listener.head_radius_m.value_or(0.0));  // 0: measured ITD
  p.hrtf_path = hrtf.empty() ? nullptr : hrtf.c_str();
  return p;
}

}  // namespace

RenderStats render_scene(const scenes::Scene& scene, const RenderOptions& opt) {
  // The world runs at whole Hz, as the WAV header says.
  const double rate = std::round(opt.sample_rate.value_or(scene.sample_rate));
  const double duration = opt.duration_s.value_or(scene.duration_s);
  if (opt.block == 0 || opt.block > 8192) throw InputError::at("--block", 0, "", "must be 1 to 8192 frames");
  if (!(rate >= 8000 && rate <= 192000)) throw InputError::at("--rate", 0, "", "must be 8000 to 192000 Hz");
  const std::string origin = scene.origin.empty() ? "scene" : scene.origin;
  if (scene.sources.size() + scene.beds.size() > kMaxSources)
    throw InputError::at(origin, 0, "sources",
                         std::to_string(scene.sources.size() + scene.beds.size()) +
                             " sources and beds; a world renders at most " + std::to_string(kMaxSources));
  const std::string quality = opt.quality.value_or(scene.quality);
  const std::optional<int> order = scenes::quality_order(quality);
  if (!order)
    throw InputError::at(opt.quality ? "--quality" : origin, 0, opt.quality ? "" : "quality",
                         "unknown quality '" + quality + "' (direct, ambisonic:1 to ambisonic:7)");
  if (opt.decoder != "magls" && opt.decoder != "ls")
    throw InputError::at("--decoder", 0, "", "unknown decoder '" + opt.decoder + "' (magls, ls)");
  const ListenerTrack listener(scene, opt.pose_track);

  const std::string hrtf = opt.hrtf.string();
  const WorldHandle world(world_params(scene, rate, opt.block, hrtf));
  const ESworld w = world.id();
  // Each block's changes land together, at that block.
  world.check(esWorldi(w, ES_COMMIT_MODE, ES_DEFERRED), origin, "");
  if (opt.decoder == "ls") world.check(esWorldi(w, ES_AMBISONIC_DECODER, ES_DECODER_LS), "--decoder", "");
  // The tier before the first block: the world's from its first sample.
  if (*order > 0) world.check(esWorldi(w, ES_QUALITY, ES_QUALITY_AMBISONIC(*order)), opt.quality ? "--quality" : origin,
                              opt.quality ? "" : "quality");
  SceneSources sources(world, rate);  // destroyed before the world
  sources.load(scene);
  listener.start(world);

  WavWriter out(opt.out, static_cast<int>(rate), opt.format);
  RenderStats stats;
  const auto total = static_cast<std::size_t>(std::llround(duration * rate));
  std::vector<float> l(opt.block), r(opt.block);
  std::size_t done = 0, next_report = 0;
  while (done < total) {
    if (opt.stop && opt.stop()) {
      stats.stopped = true;
      break;  // `out` closes below: libsndfile writes the header's final sizes
    }
    const double t = static_cast<double>(done) / rate;
    listener.at(world, t);
    sources.move(t);
    world.check(esCommit(w), origin, "");
    // esRender keeps no message (it runs on an audio thread): only a code.
    if (const ESenum e = esRender(w, l.data(), r.data(), static_cast<ESuint>(opt.block)); e != ES_OK)
      throw std::runtime_error(std::string("esRender: ") + esGetErrorString(e));
    const std::size_t n = std::min(opt.block, total - done);
    for (std::size_t i = 0; i < n; ++i)
      stats.peak = std::max({stats.peak, double(std::abs(l[i])), double(std::abs(r[i]))});
    out.write({l.data(), n}, {r.data(), n});
    done += n;
    if (opt.progress && done >= next_report) {
      opt.progress(static_cast<double>(done) / static_cast<double>(total));
      next_report = done + total / 100 + 1;
    }
  }
  out.close();
  stats.frames = done;
  return stats;
}

}  // namespace earshot::host
