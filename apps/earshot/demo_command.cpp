// `earshot demo`: the README's main job. A scene (Circles by default) heard
// by a head that a tracker follows (the simulated Wii camera by default).
// Where there is no audio device or no display to play and show it on, it
// says so and renders the same thing to a WAV file, with the head's poses
// beside it as a Pose track CSV, so it can be listened to anywhere and
// replayed through `earshot render`.
#include "demo_command.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <variant>

#include "earshot/errors.hpp"
#include "earshot/geometry.hpp"
#include "earshot/host/rooms.hpp"
#include "earshot/host/scene_render.hpp"
#include "earshot/scenes/field_stream.hpp"
#include "earshot/scenes/presets.hpp"
#include "earshot/scenes/scene.hpp"
#include "earshot/stop_signals.hpp"
#include "earshot/tracker/live/live_pipeline.hpp"
#include "earshot/pose_track_csv.hpp"
#include "earshot/tracker/live/source_spec.hpp"
#include "earshot/tracker/send/send_spec.hpp"
#include "demo/audio_output.hpp"
#include "demo/keys.hpp"
#include "demo/live_demo.hpp"
#include "progress_bar.hpp"

namespace earshot::app {
namespace {

struct DemoArgs {
  std::string scene = "circles", room, tracker = "sim", out = "earshot-demo.wav";
  std::string ambix;         ///< an Ambisonic file played as a bed (alone unless --scene is given too)
  bool scene_given = false;  ///< --scene was on the command line
  std::vector<std::string> hrtfs;  ///< --hrtf, repeatable: 'h' switches among them live
  double duration = -1;
  std::uint64_t seed = 1;
  std::string device, capture, capture_poses;
  unsigned long buffer = 128;
  bool list_devices = false, no_window = false;
  std::string screenshot;
  std::string listen;  ///< the pose tracker's listen address (--listen)
  std::vector<std::string> send;  ///< where the tracker also sends its poses (--send)
  std::string why;  ///< why it renders instead of playing (empty: found here)
};

/// True when PortAudio should be tried: a device was named or a sound card exists.
bool want_live(const DemoArgs& a) {
  if (!a.device.empty() || a.list_devices) return true;
  std::ifstream pcm("/proc/asound/pcm");
  std::string line;
  return pcm && std::getline(pcm, line) && !line.empty();
}

/// Why live output cannot happen here, or empty when it could.
std::string why_offline() {
  std::string why;
  std::ifstream pcm("/proc/asound/pcm");
  std::string line;
  const bool sound = pcm && std::getline(pcm, line) && !line.empty();
  if (!sound) why += "no audio device (no sound card in /proc/asound)";
  if (!std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY")) why += std::string(why.empty() ? "" : ", ") + "no display";
  if (why.empty()) why = "this build has no real-time output yet";
  return why;
}

struct TrackedHead {
  long frames = 0, tracked = 0;
  double yaw_min = 0, yaw_max = 0;
};

/// Runs the tracker pipeline over the source as fast as it goes and writes
/// the listener's poses as a Pose track CSV.
TrackedHead track_to_file(const DemoArgs& a, double duration, const std::filesystem::path& poses) {
  tracker::LiveConfig cfg;
  const auto spec = tracker::parse_source_spec(a.tracker, "--tracker");
  using Kind = tracker::SourceSpec::Kind;
  if (spec.kind != Kind::sim && spec.kind != Kind::replay)
    throw InputError::at("--tracker", 0, "",
                         "'" + a.tracker + "' cannot run offline (sim or replay:DOTS.csv; live trackers need "
                         "real-time output: see `earshot track live`)");
  tracker::SourceOptions so;
  so.pacing = tracker::Pacing::as_fast_as_possible;
  so.camera = cfg.camera;
  so.model = cfg.model;
  so.sim.sim.seed = a.seed;
  so.sim.frames = static_cast<long>(std::ceil(duration * so.sim.sim.rate_hz)) + 1;
  const auto source = tracker::make_frame_source(spec, so);
  tracker::LivePipeline pipeline(cfg);
  pipeline.request_recenter();  // the first pose seen is straight ahead
  std::ofstream out(poses);
  if (!out) throw InputError::at(poses.string(), 0, "", "cannot write");
  PoseTrackCsvWriter writer(out);
  TrackedHead head;
  for (;;) {
    const tracker::SourceEvent e = source->next(std::chrono::milliseconds(0));
    if (const auto* n = std::get_if<tracker::SourceNote>(&e); n && n->kind == tracker::SourceNote::Kind::ended) break;
    const auto p = pipeline.process(e, 0.0);
    if (!p || std::holds_alternative<tracker::SourceNote>(e)) continue;
    ++head.frames;
    if (p->state == PoseState::tracking || p->state == PoseState::predicted) ++head.tracked;
    const double yaw = ypr_from_quat(p->orientation).yaw * 180.0 / std::numbers::pi;
    head.yaw_min = std::min(head.yaw_min, yaw);
    head.yaw_max = std::max(head.yaw_max, yaw);
    writer.write(*p);
    if (p->t > duration) break;
  }
  return head;
}


void run_offline(const DemoArgs& a);

void run_demo(const DemoArgs& a) {
  if (a.list_devices) {
    demo::list_devices();
    return;
  }
  if (want_live(a)) {
    demo::LiveOptions o;
    o.scene = a.scene, o.room = a.room, o.tracker = a.tracker, o.device = a.device, o.hrtfs = a.hrtfs;
    o.ambix = a.ambix, o.ambix_alone = !a.scene_given;
    o.buffer = a.buffer, o.duration = a.duration, o.capture = a.capture, o.capture_poses = a.capture_poses;
    o.send = a.send;
    o.window = !a.no_window, o.screenshot = a.screenshot;
    try {
      const long xruns = demo::run_live(o);
      if (xruns > 0) std::printf("  (%ld xruns: try a larger --buffer)\n", xruns);
      return;
    } catch (const demo::NoDevice& e) {
      DemoArgs off = a;
      off.why = e.what();
      run_offline(off);
      return;
    }
  }
  run_offline(a);
}

void run_offline(const DemoArgs& a) {
  const bool field_alone = !a.ambix.empty() && !a.scene_given;
  const std::filesystem::path scene_file = field_alone ? std::filesystem::path(a.ambix) : scenes::resolve_scene_argument(a.scene);
  scenes::Scene scene = field_alone ? scenes::scene_of_field(a.ambix) : scenes::load_scene(scene_file);
  if (!a.ambix.empty() && !field_alone) scene.beds.push_back(scenes::scene_of_field(a.ambix).beds.front());
  if (!a.room.empty()) scene.room = scenes::checked_room_name(a.room, "--room");
  const double duration = a.duration > 0 ? a.duration : scene.duration_s;
  std::filesystem::path out(a.out), poses = out;
  poses.replace_extension(".poses.csv");

  std::printf("earshot demo: %s; rendering to %s instead of playing.\n",
              a.why.empty() ? why_offline().c_str() : a.why.c_str(), out.c_str());
  if (!a.send.empty())
    std::printf("  --send: nothing is sent while rendering to a file (the tracker runs faster than real time);\n"
                "  `earshot track live --send` sends a tracker's poses without playing\n");
  std::printf("  scene   %s (%zu sources, %zu beds, room %s)\n", scene_file.c_str(), scene.sources.size(),
              scene.beds.size(), scene.room.c_str());
  const TrackedHead head = track_to_file(a, duration, poses);
  std::printf("  tracker %s: %ld frames, %.1f%% tracked, head yaw %+.0f to %+.0f deg -> %s\n", a.tracker.c_str(),
              head.frames, head.frames ? 100.0 * double(head.tracked) / double(head.frames) : 0.0, head.yaw_min,
              head.yaw_max, poses.c_str());
  host::RenderOptions o;
  o.out = out;
  o.duration_s = duration;
  if (!a.hrtfs.empty()) o.hrtf = a.hrtfs.front();  // offline: the first set
  o.pose_track = poses;
  if (isatty(STDERR_FILENO)) o.progress = progress_bar;
  const StopSignals stop;  // as `earshot render`: a signal leaves a valid, shorter WAV
  o.stop = [&stop] { return stop.requested(); };
  const auto st = host::render_scene(scene, o);
  if (st.stopped)
    throw std::runtime_error("stopped by " + std::string(StopSignals::name(stop.signal())) + ": " + out.string() +
                             " is a valid WAV of the first " + std::to_string(st.frames) + " frames only");
  std::printf("  audio   %s: %.1f s binaural at %.0f Hz, peak %.3f (HRTF %s)\n", out.c_str(),
              double(st.frames) / scene.sample_rate, scene.sample_rate, st.peak,
              a.hrtfs.empty() ? "MIT KEMAR" : a.hrtfs.front().c_str());
  if (field_alone)
    std::printf("Listen on headphones; the sound field stays in place while the head turns. Replay with\n"
                "  earshot render --ambix %s --pose-track %s --out again.wav\n", a.ambix.c_str(), poses.c_str());
  else
    std::printf("Listen on headphones; the sources keep their places while the head turns. Replay with\n"
                "  earshot render --scene %s --pose-track %s --out again.wav\n", a.scene.c_str(), poses.c_str());
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto a = std::make_shared<DemoArgs>();
  auto* demo = app.add_subcommand("demo", "Hear a scene through a tracked head (defaults: simulated tracker, "
                                          "MIT KEMAR, Circles); renders to a WAV where it cannot play");
  auto* scene_option =
      demo->add_option("--scene,-s", a->scene, "Scene JSON or a shipped preset (manual, circles, traffic, zoo, teleconference)")
          ->capture_default_str();
  demo->add_option("--ambix", a->ambix,
                   "An Ambisonic file (ambiX; order from the channel count) played as a sound field around the "
                   "tracked head: alone, or as a bed in --scene's scene");
  demo->add_option("--room", a->room, "Room preset overriding the scene's (e.g. concert-hall, none)");
  demo->add_option("--tracker", a->tracker,
                   "Head tracker: sim, replay:DOTS.csv; live also wiimote, opentrack[:PORT][@ADDR], osc[:PORT][@ADDR], none")
      ->capture_default_str();
  demo->add_option("--listen", a->listen,
                   "Pose trackers (opentrack, osc): the IPv4 address to listen on (default 127.0.0.1; 0.0.0.0 for "
                   "every interface: anyone on the network could then turn your head)");
  demo->add_option("--send", a->send,
                   "Live: also send the tracker's poses on (repeatable): " + std::string(tracker::kSendSpecs) +
                       " (docs/OSC.md)");
  demo->add_option("--device", a->device, "Audio output device (name or part of it; see --list-devices)");
  demo->add_flag("--list-devices", a->list_devices, "List the audio output devices and exit");
  demo->add_option("--buffer", a->buffer, "Frames per audio buffer (and plugin block)")
      ->capture_default_str()
      ->check(CLI::Range(16, 8192));
  demo->add_option("--capture", a->capture, "Live: also write what the audio callback played to this WAV");
  demo->add_option("--capture-poses", a->capture_poses, "Live: write the head's yaw per control tick (CSV)");
  demo->add_flag("--no-window", a->no_window, "Live: status line on the terminal even with a display");
  demo->add_option("--screenshot", a->screenshot, "Live with a window: PNG of its last frame at the end");
  demo->footer("Keys while playing (window and terminal): " + demo::keys_line() +
               ".\n"
               "Plays through PortAudio when there is a sound card or --device is given (e.g. a JACK server);\n"
               "otherwise says why and renders the same scene to --out. Live, the tracker's state and messages\n"
               "(no remote found, disconnected, lost) show in the window and on the terminal; a scene file\n"
               "with errors is named with its error and Circles plays instead.");
  demo->add_option("--hrtf", a->hrtfs,
                   "SOFA file (default: MIT KEMAR from libmysofa); repeat it to switch among sets live with 'h'");
  demo->add_option("--out,-o", a->out, "WAV file written when it cannot play")->capture_default_str();
  demo->add_option("--duration", a->duration, "Seconds (default: the scene's)");
  demo->add_option("--seed", a->seed, "Seed of the simulated head's walk")->capture_default_str();
  demo->callback([a, scene_option] {
    DemoArgs args = *a;
    args.scene_given = scene_option->count() > 0;
    if (!args.listen.empty()) args.tracker = tracker::with_listen_address(args.tracker, args.listen, "--tracker", "--listen");
    for (const std::string& s : args.send) (void)tracker::parse_send_spec(s, "--send");  // a bad spec: an input error now
    run_demo(args);
  });
}

}  // namespace earshot::app
