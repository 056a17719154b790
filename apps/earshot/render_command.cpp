#include "render_command.hpp"

#include <unistd.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/host/scene_render.hpp"
#include "earshot/scenes/field_stream.hpp"
#include "earshot/scenes/presets.hpp"
#include "earshot/stop_signals.hpp"
#include "progress_bar.hpp"

namespace earshot::app {

namespace {
struct RenderArgs {
  std::string scene, ambix, convention = "ambix", out, hrtf, pose_track, format = "float", quality, decoder = "magls";
  double duration = -1, rate = -1;
  std::size_t block = 128;
};

}  // namespace

void add_render_command(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand("render", "Render a Scene JSON or an Ambisonic file offline to a WAV file (deterministic)");
  auto* scene_option = cmd->add_option("--scene,-s", a->scene,
                                "Scene JSON file, or a shipped preset's name (manual, circles, traffic, zoo, teleconference)");
  auto* ambix = cmd->add_option("--ambix", a->ambix,
                                "An Ambisonic file (WAV, CAF, W64, ...; ambiX: ACN, SN3D; order from the channel count) "
                                "rendered for the listener's head, at the file's rate unless --rate");
  scene_option->excludes(ambix);
  ambix->excludes(scene_option);
  cmd->add_option("--convention", a->convention, "The --ambix file's convention: ambix, n3d or fuma (orders 1-3)")
      ->capture_default_str()
      ->check(CLI::IsMember({"ambix", "n3d", "fuma"}));
  cmd->add_option("--decoder", a->decoder,
                  "Binaural decoder of Ambisonic beds and of the ambisonic tier: magls (default) or ls")
      ->capture_default_str()
      ->check(CLI::IsMember({"magls", "ls"}));
  cmd->add_option("--quality", a->quality,
                  "Renderer tier for the point sources: direct (default: the scene's) or ambisonic:N (N = 1..7)");
  cmd->add_option("--out,-o", a->out,
                  "WAV file to write (stopped by SIGINT, SIGTERM or SIGHUP: the frames so far, a valid WAV; exit 1)")
      ->required();
  cmd->add_option("--duration", a->duration, "Seconds (default: the scene's duration_s)");
  cmd->add_option("--rate", a->rate, "Sample rate, Hz (default: the scene's sample_rate)");
  cmd->add_option("--block", a->block, "Frames per block")->capture_default_str();
  cmd->add_option("--hrtf", a->hrtf, "SOFA file (default: MIT KEMAR from libmysofa)");
  cmd->add_option("--pose-track", a->pose_track, "Pose track CSV for the listener (t_s,x_m,y_m,z_m,qw,qx,qy,qz)");
  cmd->add_option("--format", a->format, "Sample format: float (32-bit) or pcm24")->capture_default_str();
  cmd->callback([a] {
    const StopSignals stop;  // first: a signal while loading stops before the first block
    host::RenderOptions o;
    o.stop = [&stop] { return stop.requested(); };
    o.out = a->out;
    if (a->duration >= 0) o.duration_s = a->duration;
    if (a->rate > 0) o.sample_rate = a->rate;
    o.block = a->block;
    o.hrtf = a->hrtf;
    if (!a->pose_track.empty()) o.pose_track = a->pose_track;
    if (a->format == "float")
      o.format = host::WavFormat::float32;
    else if (a->format == "pcm24")
      o.format = host::WavFormat::pcm24;
    else
      throw InputError::at("--format", 0, "", "unknown format '" + a->format + "' (float, pcm24)");
    if (!a->quality.empty()) o.quality = a->quality;
    o.decoder = a->decoder;
    if (a->scene.empty() && a->ambix.empty()) throw InputError::at("render", 0, "", "--scene or --ambix is required");
    if (isatty(STDERR_FILENO)) o.progress = progress_bar;
    const auto scene =
        a->ambix.empty() ? scenes::load_scene(scenes::resolve_scene_argument(a->scene)) : scenes::scene_of_field(a->ambix, a->convention);
    const auto st = host::render_scene(scene, o);
    if (st.stopped) {
      if (o.progress) std::fputc('\n', stderr);
      throw std::runtime_error("stopped by " + std::string(StopSignals::name(stop.signal())) + ": " + a->out +
                               " is a valid WAV of the first " + std::to_string(st.frames) + " frames only");
    }
    if (scene.beds.empty())
      std::printf("wrote %s: %zu frames, %zu sources, peak %.3f\n", a->out.c_str(), st.frames, scene.sources.size(),
                  st.peak);
    else
      std::printf("wrote %s: %zu frames, %zu sources, %zu beds, peak %.3f\n", a->out.c_str(), st.frames,
                  scene.sources.size(), scene.beds.size(), st.peak);
  });
}

}  // namespace earshot::app
