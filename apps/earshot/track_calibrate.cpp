// `earshot track calibrate`: the LED model from a recording of the head
// moving in front of the camera (tracker/calibration/include/earshot/tracker/calibration/led_calibration.hpp).
#include "track_calibrate.hpp"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/calibration/led_calibration.hpp"

namespace earshot::app {
namespace {

using namespace earshot::tracker;

struct CalibrateOptions {
  std::string dots, model, out, scale;
  double focal = 1280.0;
  bool estimate_focal = false;
  size_t max_frames = 6000;
  double max_sigma_mm = 1.0;
};

void run_calibrate(const CalibrateOptions& o) {
  const ScaleBar bar = parse_scale_bar(o.scale);
  const LedModel start = load_led_model(o.model);
  std::fprintf(stderr, "calibrate: reading %s\n", o.dots.c_str());
  const std::vector<DotFrame> frames = read_dots_csv(o.dots);
  CalibrationOptions opt;
  opt.scale = bar;
  opt.estimate_focal = o.estimate_focal;
  opt.max_frames = o.max_frames;
  opt.max_led_sigma_mm = o.max_sigma_mm;
  opt.on_progress = [](const std::string& s) { std::fprintf(stderr, "calibrate: %s\n", s.c_str()); };
  opt.on_iteration = [](const CalibrationIteration& it) {
    if (it.iteration > 0 && it.iteration % 5 != 0) return;
    std::fprintf(stderr, "calibrate: round %d step %d: RMS residual %.3f px, focal %.1f px\n", it.round, it.iteration,
                 it.rms_px, it.focal_px);
  };
  const CalibrationResult r = calibrate_led_model(frames, start, Camera::with_focal(o.focal), opt, o.dots);
  save_led_model(r.model, o.out);

  std::printf("frames            %zu read, %zu with four LEDs labelled, %zu used\n", r.frames_read, r.frames_four,
              r.frames_used);
  std::printf("head motion       yaw %.1f deg, pitch %.1f deg, roll %.1f deg, depth %.0f mm (5th-95th percentile)\n",
              r.motion.yaw_deg, r.motion.pitch_deg, r.motion.roll_deg, r.motion.depth_mm);
  std::printf("RMS residual      %.3f px with the starting model, %.3f px calibrated (pixel noise %.3f px, %zu dots "
              "down-weighted as outliers)\n",
              r.rms_before_px, r.rms_after_px, r.pixel_sigma_px, r.outlier_dots);
  std::printf("scale             LEDs %d-%d at %.2f mm (ruler)\n", bar.a, bar.b, bar.mm);
  if (o.estimate_focal)
    std::printf("focal length      %.1f px +- %.1f (started from %.1f): pass --focal %.1f to the other commands\n",
                r.focal_px, r.focal_sigma_px, o.focal, r.focal_px);
  std::printf("LED  x mm       y mm       z mm       sigma x/y/z mm          moved mm\n");
  for (size_t j = 0; j < 4; ++j) {
    const tracker::Vec3& p = r.model.leds_mm[j];
    const tracker::Vec3& s = r.led_sigma_mm[j];
    std::printf("%zu   %9.3f  %9.3f  %9.3f   %6.3f %6.3f %6.3f    %7.3f\n", j, p.x(), p.y(), p.z(), s.x(), s.y(),
                s.z(), r.moved_mm[j]);
  }
  std::printf("least determined (sigma along each direction):\n");
  for (const auto& w : r.weakest)
    std::printf("  %.3f %s: %s\n", w.sigma_mm, w.focal_share > 0.5 ? "px" : "mm", w.description.c_str());
  if (r.advice.empty())
    std::printf("advice            none: the motion determined every LED\n");
  else
    for (const auto& a : r.advice) std::printf("advice            %s\n", a.c_str());
  std::printf("wrote %s\n", o.out.c_str());
}

}  // namespace

void add_track_calibrate_command(CLI::App& track) {
  auto o = std::make_shared<CalibrateOptions>();
  auto* cmd = track.add_subcommand(
      "calibrate",
      "Estimate the beacon's LED positions (and optionally the focal length) from a recording of the head moving; "
      "writes a Model JSON");
  cmd->add_option("--dots,-d", o->dots, "Dots CSV of the session (track record / track simulate)")->required();
  cmd->add_option("--model", o->model, "Model JSON to start from (the LEDs as measured, within a few mm)")->required();
  cmd->add_option("--out,-o", o->out, "Model JSON to write")->required();
  cmd->add_option("--scale-mm", o->scale,
                  "D:A-B, the distance D in mm between LEDs A and B (0-based) measured with a ruler, e.g. 127:0-1")
      ->required();
  cmd->add_option("--focal", o->focal, "Focal length in pixels (the start with --estimate-focal)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--estimate-focal", o->estimate_focal, "Estimate the focal length too");
  cmd->add_option("--max-frames", o->max_frames, "Four-dot frames used, spread over the session")
      ->capture_default_str()
      ->check(CLI::Range(100, 1000000));
  cmd->add_option("--max-sigma", o->max_sigma_mm, "Refuse a model with an LED less certain than this, mm")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->callback([o] { run_calibrate(*o); });
}

}  // namespace earshot::app
