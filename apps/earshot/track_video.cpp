// `earshot track simulate-video`: renders a head walk as a webcam would see
// it (webcam/sim: LED spots or a printed AprilTag, motion blur, noise,
// auto-exposure drift) into a YUV4MPEG2 file for the webcam source's file
// player, and writes the ground truth as a Dots CSV: each frame's projected
// beacon points in label order (slot k = LED k or tag corner k) and the pose,
// in the tracker's own format (its Dots CSV reader parses it).
#include "track_video.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/led_model.hpp"
#include "earshot/tracker/sim/simulator.hpp"
#include "earshot/webcam/video_sim.hpp"
#include "earshot/webcam/y4m_writer.hpp"

namespace earshot::app {
namespace {

using namespace earshot::webcam;

struct VideoOptions {
  std::string beacon = "leds";
  double size_mm = 80.0;
  std::string family = "tag36h11";
  int id = 0;
  std::string resolution = "640x480";
  double fps = 30.0;
  double hfov_deg = 60.0;
  std::string motion = "seated";
  double seconds = 10.0;
  std::uint64_t seed = 1;
  std::string model_path;
  bool lamp = false;
  bool clean = false;
  std::string out;
  std::string truth;
};

void parse_resolution(const std::string& s, int& w, int& h) {
  const auto x = s.find('x');
  auto bad = [&] { throw InputError("--resolution: expected WIDTHxHEIGHT (e.g. 640x480), got '" + s + "'"); };
  if (x == std::string::npos || x == 0 || x + 1 >= s.size()) bad();
  try {
    size_t used = 0;
    w = std::stoi(s.substr(0, x), &used);
    if (used != x) bad();
    h = std::stoi(s.substr(x + 1), &used);
    if (used != s.size() - x - 1) bad();
  } catch (const std::logic_error&) {
    bad();
  }
  if (w < 8 || h < 8 || w > 8192 || h > 8192) throw InputError("--resolution: " + s + " is outside 8x8..8192x8192");
}

void run_video(const VideoOptions& o) {
  VideoSimConfig cfg;
  if (o.beacon == "leds") {
    cfg.beacon = BeaconKind::leds;
    if (!o.model_path.empty()) cfg.leds = tracker::load_led_model(o.model_path);
  } else if (o.beacon == "apriltag") {
    cfg.beacon = BeaconKind::apriltag;
  } else {
    throw InputError("--beacon: expected leds or apriltag, got '" + o.beacon + "'");
  }
  const auto motion = tracker::motion_profile_from(o.motion);
  if (!motion) throw InputError("--motion: unknown profile '" + o.motion + "' (walk, seated, orienting, nodding, walking, tremor, mixed)");
  parse_resolution(o.resolution, cfg.width, cfg.height);
  cfg.motion = *motion;
  cfg.fps = o.fps;
  cfg.hfov_deg = o.hfov_deg;
  cfg.seed = o.seed;
  cfg.family = o.family;
  cfg.id = o.id;
  cfg.tag_size_mm = o.size_mm;
  cfg.lamp = o.lamp;
  cfg.exposure_s = std::min(cfg.exposure_s, 1.0 / o.fps);
  if (o.clean) {
    cfg.read_noise = cfg.shot_noise = 0.0;
    cfg.auto_exposure = false;
    cfg.motion_samples = 1;
  }
  VideoSimulator sim(cfg);  // std::invalid_argument names a bad setting

  // F<num>:<den>: whole rates as N:1, others to a thousandth.
  const bool whole = std::abs(o.fps - std::round(o.fps)) < 1e-9;
  const int num = whole ? static_cast<int>(std::lround(o.fps)) : static_cast<int>(std::lround(o.fps * 1000.0));
  Y4mWriter video(o.out, cfg.width, cfg.height, num, whole ? 1 : 1000);
  std::ofstream truth_file;
  std::unique_ptr<tracker::DotsCsvWriter> truth;
  if (!o.truth.empty()) {
    truth_file.open(o.truth);
    if (!truth_file) throw InputError(o.truth + ": cannot open for writing");
    truth = std::make_unique<tracker::DotsCsvWriter>(truth_file, true);
  }
  const long frames = std::max(1L, std::lround(o.seconds * o.fps));
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  VideoFrame f;
  long all_four = 0;
  for (long i = 0; i < frames; ++i) {
    sim.next(f);
    video.write(f.pixels);
    if (truth) truth->write(f.dot_frame());
    int seen = 0;
    for (const auto& p : f.points) seen += p.has_value();
    all_four += seen == 4;
    // A progress line once a second of video (in place on a terminal).
    if ((i + 1) % std::max(1L, std::lround(o.fps)) == 0 || i + 1 == frames)
      std::fprintf(stderr, tty ? "\rrendered %ld / %ld frames" : "rendered %ld / %ld frames\n", i + 1, frames);
  }
  if (tty) std::fprintf(stderr, "\n");
  video.close();
  if (truth) {
    truth_file.flush();
    if (!truth_file) throw InputError(o.truth + ": write failed");
  }
  const tracker::Camera& cam = sim.camera();
  std::printf("wrote %s: %ld frames %dx%d at %g frames/s, %s, %s motion, seed %llu\n", o.out.c_str(), frames, cfg.width,
              cfg.height, o.fps, o.beacon == "leds" ? "LED beacon" : (o.family + " id " + std::to_string(o.id) + ", " +
                                                                       std::to_string(static_cast<int>(o.size_mm)) + " mm").c_str(),
              o.motion.c_str(), static_cast<unsigned long long>(o.seed));
  std::printf("camera: focal %.1f px (%.0f deg horizontal), principal point (%.1f, %.1f); all four points in view in %ld frames\n",
              cam.fx, o.hfov_deg, cam.cx, cam.cy, all_four);
  if (truth) std::printf("truth: %s (Dots CSV: projected points in label order, pose)\n", o.truth.c_str());
}

}  // namespace

void add_track_video_commands(CLI::App& track) {
  auto o = std::make_shared<VideoOptions>();
  auto* cmd = track.add_subcommand(
      "simulate-video",
      "Render synthetic webcam video of a head walk (LED beacon or AprilTag) as a Y4M file, with its ground truth");
  cmd->add_option("--out,-o", o->out, "Y4M file to write (8-bit grey, Cmono)")->required();
  cmd->add_option("--truth", o->truth, "Ground truth to write: Dots CSV of the projected points and the pose");
  cmd->add_option("--beacon", o->beacon, "leds (the thesis beacon, or --model) or apriltag")->capture_default_str();
  cmd->add_option("--size-mm", o->size_mm, "Tag's outer black square, mm")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--family", o->family, "Tag family (tag36h11, tag25h9, tag16h5, tagStandard41h12, ...)")->capture_default_str();
  cmd->add_option("--id", o->id, "Tag id")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--resolution", o->resolution, "WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--fps", o->fps, "Frames per second")->capture_default_str()->check(CLI::Range(0.1, 1000.0));
  cmd->add_option("--hfov", o->hfov_deg, "Horizontal field of view, degrees")->capture_default_str()->check(CLI::Range(5.0, 150.0));
  cmd->add_option("--motion", o->motion, "Head motion: walk, seated, orienting, nodding, walking, tremor, mixed")->capture_default_str();
  cmd->add_option("--seconds", o->seconds, "Length of the video")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--seed", o->seed, "Random seed (motion, scene, noise)")->capture_default_str();
  cmd->add_option("--model", o->model_path, "Model JSON with the LED positions (--beacon leds)");
  cmd->add_flag("--lamp", o->lamp, "Put a bright lamp in the scene (the LED detector must reject it)");
  cmd->add_flag("--clean", o->clean, "No noise, motion blur or exposure drift");
  cmd->callback([o] { run_video(*o); });
}

}  // namespace earshot::app
