#include "track_commands.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "earshot/errors.hpp"
#include "earshot/tracker/track/accuracy.hpp"
#include "earshot/tracker/track/dot_tracker.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/filter/eskf.hpp"
#include "earshot/tracker/core/led_model.hpp"
#include "earshot/tracker/core/poses_csv.hpp"
#include "earshot/tracker/filter/segment_vetting.hpp"
#include "earshot/tracker/sim/head_trace.hpp"
#include "earshot/tracker/sim/simulator.hpp"
#include "track_calibrate.hpp"
#include "track_video.hpp"

namespace earshot::app {
namespace {

using namespace earshot::tracker;

struct CameraOptions {
  double focal = 1280.0;
  std::string model_path;

  void add_to(CLI::App& cmd) {
    cmd.add_option("--focal", focal, "Camera focal length in pixels (1024x768 image)")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd.add_option("--model", model_path, "Model JSON with the beacon's LED positions (default: thesis beacon)");
  }
  [[nodiscard]] Camera camera() const { return Camera::with_focal(focal); }
  [[nodiscard]] LedModel model() const { return model_path.empty() ? LedModel::thesis() : load_led_model(model_path); }
};

struct SimulateOptions {
  CameraOptions cam;
  SimulatorConfig sim;
  long frames = 10000;
  bool frames_given = false;
  std::string pixels = "integer";
  std::string motion = "walk";
  std::string out;
};

struct SolveOptions {
  CameraOptions cam;
  std::string dots;
  std::string out;
  std::string method = "lm";
  std::string filter = "auto";
  double gate_px = 4.0;
  bool smooth = false;
};

/// What a tracking run did, and how well when ground truth is known.
struct Summary {
  long frames = 0, tracking = 0, predicted = 0, lost = 0;
  double reproj_sum = 0.0;
  TrackingTally tally;

  void add(const DotFrame& f, const TrackResult& r) {
    add(leds_seen(f), f.truth ? std::optional<Pose>(f.truth->pose) : std::nullopt, r.state, r.rms_px, r.pose);
  }
  void add(int leds, const std::optional<Pose>& truth, PoseState state, double rms_px, const Pose& pose) {
    ++frames;
    if (state == PoseState::tracking) {
      ++tracking;
      reproj_sum += rms_px;
    } else if (state == PoseState::predicted) {
      ++predicted;
    } else {
      ++lost;
    }
    tally.add(leds, truth, state == PoseState::tracking, pose);
  }

  void print(std::FILE* out, std::string_view method) const {
    auto pct = [](long a, long b) { return b ? 100.0 * static_cast<double>(a) / static_cast<double>(b) : 0.0; };
    std::fprintf(out, "method            %.*s\n", static_cast<int>(method.size()), method.data());
    std::fprintf(out, "frames            %ld\n", frames);
    std::fprintf(out, "tracked           %.2f %%  (predicted %.2f %%, lost %.2f %%)\n", pct(tracking, frames),
                 pct(predicted, frames), pct(lost, frames));
    std::fprintf(out, "tracked of frames with >= 3 dots  %.3f %%  (%ld of %ld)\n", pct(tally.tracked_3plus, tally.frames_3plus),
                 tally.tracked_3plus, tally.frames_3plus);
    std::fprintf(out, "mean reprojection error  %.3f px\n", tracking ? reproj_sum / static_cast<double>(tracking) : 0.0);
    if (tally.all.count() == 0) return;
    auto row = [&](const char* name, const ErrorStats& s, const char* unit) {
      std::fprintf(out, "%-26s RMS %8.3f  p95 %8.3f  max %9.3f %s  (n=%zu)\n", name, s.rms, s.p95, s.max, unit, s.count);
    };
    row("rotation error", tally.all.rotation_deg(), "deg");
    row("translation error", tally.all.translation_mm(), "mm");
    row("rotation error, 4 dots", tally.four_dot.rotation_deg(), "deg");
    row("translation error, 4 dots", tally.four_dot.translation_mm(), "mm");
    std::fprintf(out, "flipped frames (> %.0f deg) %ld\n", kFlipDeg, tally.flips);
  }
};

std::ostream& open_out(const std::string& path, std::ofstream& file) {
  if (path == "-") return std::cout;
  file.open(path);
  if (!file) throw InputError::at(path, 0, "", "cannot create file");
  return file;
}

void run_simulate(const SimulateOptions& o) {
  SimulatorConfig cfg = o.sim;
  const auto px = pixel_model_from(o.pixels);
  if (!px) throw InputError::at("--pixels", 0, "", "unknown pixel model '" + o.pixels + "'");
  cfg.pixels = *px;
  long frames = o.frames;
  if (o.motion.starts_with("trace:")) {
    // A recorded head (head_trace.hpp); the whole trace unless --frames is given.
    cfg.trace = std::make_shared<const HeadTrace>(HeadTrace::load(o.motion.substr(6)));
    if (!o.frames_given) frames = static_cast<long>(cfg.trace->duration() * cfg.rate_hz);
  } else {
    const auto motion = motion_profile_from(o.motion);
    if (!motion)
      throw InputError::at("--motion", 0, "",
                           "unknown motion '" + o.motion +
                               "' (walk, seated, orienting, nodding, walking, tremor, mixed, listener, sweep, trace:FILE)");
    cfg.motion = *motion;
  }
  Simulator sim(o.cam.camera(), o.cam.model(), cfg);
  std::ofstream file;
  std::ostream& out = open_out(o.out, file);
  DotsCsvWriter w(out, true);
  SpeedCollector speed;
  long seen3 = 0;
  for (long i = 0; i < frames; ++i) {
    const DotFrame f = sim.next();
    speed.add(f.truth->pose, f.t);
    if (leds_seen(f) >= 3) ++seen3;
    w.write(f);
  }
  out.flush();
  if (!out) throw InputError::at(o.out, 0, "", "write failed");
  const SpeedStats st = speed.stats();
  std::FILE* info = o.out == "-" ? stderr : stdout;
  std::fprintf(info, "motion %s: angular speed p50 %.1f  p99 %.1f  max %.1f deg/s; %.2f %% of frames with >= 3 LEDs seen\n",
               o.motion.c_str(), st.p50, st.p99, st.max, 100.0 * static_cast<double>(seen3) / static_cast<double>(std::max(1L, frames)));
}

TrackerConfig tracker_config(const std::string& method, const std::string& filter, double gate) {
  TrackerConfig cfg;
  const auto m = solver_method_from(method);
  if (!m) throw InputError::at("--method", 0, "", "unknown method '" + method + "' (thesis, lm)");
  cfg.method = *m;
  // auto: the eskf for lm (never worse than raw LM on any profile of
  // tests/bench/tracker_motion); the thesis method has its own median.
  const std::string name = filter != "auto" ? filter : (cfg.method == SolverMethod::lm ? "eskf" : "none");
  const auto f = filter_kind_from(name);
  if (!f) throw InputError::at("--filter", 0, "", "unknown filter '" + filter + "' (auto, none, one-euro, median5, eskf)");
  cfg.filter = *f;
  cfg.labeller.fit_gate_px = gate;
  return cfg;
}

void run_solve(const SolveOptions& o) {
  std::ifstream in(o.dots);
  if (!in) throw InputError::at(o.dots, 0, "", "cannot open file");
  DotsCsvReader reader(in, o.dots);
  const TrackerConfig cfg = tracker_config(o.method, o.filter, o.gate_px);
  if (o.smooth && cfg.filter != FilterKind::eskf)
    throw InputError::at("--smooth", 0, "", "smoothing runs over the eskf's model: use it with --filter eskf (or auto with --method lm)");
  DotTracker tracker(o.cam.camera(), o.cam.model(), cfg);
  std::ofstream file;
  std::optional<PosesCsvWriter> writer;
  if (!o.out.empty()) writer.emplace(open_out(o.out, file));
  Summary sum;
  if (!o.smooth) {
    while (auto f = reader.next()) {
      const TrackResult r = tracker.process(*f);
      if (writer) writer->write({r.t, r.state, r.pose});
      sum.add(*f, r);
    }
  } else {
    // Offline: filter the whole file forward, then smooth the tracked frames
    // backwards (Rauch-Tung-Striebel over the same motion model). Kept per
    // frame: what is written and summarised, not the frame or the step.
    struct Kept {
      double t, rms_px;
      PoseState state;
      int leds;
      Pose pose;
      std::optional<Pose> truth;
    };
    std::vector<Kept> kept;
    RtsSmoother smoother;
    std::vector<size_t> step_frame;
    while (auto f = reader.next()) {
      const TrackResult r = tracker.process(*f);
      kept.push_back({r.t, r.rms_px, r.state, leds_seen(*f), r.pose, f->truth ? std::optional<Pose>(f->truth->pose) : std::nullopt});
      if (r.state == PoseState::tracking) {
        smoother.add(tracker.eskf().last_step());
        step_frame.push_back(kept.size() - 1);
      }
    }
    // A segment no head motion connects to its neighbours (a wrong branch
    // the live tracker gave out until the evidence came) is not vouched
    // for: those frames are lost, holding the last kept pose.
    const std::vector<Pose> smooth = smoother.smooth();
    const std::vector<bool> vouched = vet_segments(smoother.segments(), smooth.size(), cfg.eskf);
    std::optional<Pose> held;
    for (size_t k = 0; k < smooth.size(); ++k) {
      Kept& frame = kept[step_frame[k]];
      if (vouched[k]) {
        frame.pose = smooth[k];
        held = smooth[k];
      } else {
        frame.state = PoseState::lost;
        if (held) frame.pose = *held;
      }
    }
    for (const Kept& k : kept) {
      if (writer) writer->write({k.t, k.state, k.pose});
      sum.add(k.leds, k.truth, k.state, k.rms_px, k.pose);
    }
  }
  sum.print(o.out == "-" ? stderr : stdout, o.smooth ? o.method + " + eskf + RTS smoother" : o.method);
}

}  // namespace

void add_track_commands(CLI::App& track) {
  auto sim_opts = std::make_shared<SimulateOptions>();
  auto* sim = track.add_subcommand("simulate", "Simulate the Wii camera watching the beacon on a seeded random walk; writes a Dots CSV with ground truth");
  sim->add_option("--out,-o", sim_opts->out, "Dots CSV to write ('-' for stdout)")->required();
  sim->add_option("--frames,-n", sim_opts->frames, "Number of frames (trace:FILE: the whole trace unless given)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber)
      ->each([sim_opts](const std::string&) { sim_opts->frames_given = true; });
  sim->add_option("--seed", sim_opts->sim.seed, "Random seed")->capture_default_str();
  sim->add_option("--rate", sim_opts->sim.rate_hz, "Camera frame rate, Hz")->capture_default_str()->check(CLI::PositiveNumber);
  sim->add_option("--motion", sim_opts->motion,
                  "Head motion: walk (the original random walk), seated, orienting (quick turns up to 500 deg/s), "
                  "nodding, walking, tremor, mixed, listener (seated, with a look away every minute or so: the demo's), "
                  "sweep (fast, reversing in one frame at its range ends), trace:FILE (a recorded head: "
                  "t_s,qw,qx,qy,qz[,x_m,y_m,z_m], see tracker/sim/.../head_trace.hpp)")
      ->capture_default_str();
  sim->add_option("--pixels", sim_opts->pixels, "Pixel model: exact, integer, quantize8 (thesis), gaussian")->capture_default_str();
  sim->add_option("--noise", sim_opts->sim.noise_px, "Pixel noise sigma for --pixels gaussian")->capture_default_str();
  sim->add_option("--z-min", sim_opts->sim.z_min_mm, "Nearest distance, mm")->capture_default_str();
  sim->add_option("--z-max", sim_opts->sim.z_max_mm, "Farthest distance, mm")->capture_default_str();
  sim->add_option("--yaw-max", sim_opts->sim.yaw_max_deg, "Yaw range +-, degrees")->capture_default_str();
  sim->add_option("--pitch-max", sim_opts->sim.pitch_max_deg, "Pitch range +-, degrees")->capture_default_str();
  sim->add_option("--roll-max", sim_opts->sim.roll_max_deg, "Roll range +-, degrees (>= 180: full circle)")->capture_default_str();
  sim->add_option("--speed", sim_opts->sim.speed_mm_s, "RMS translation speed, mm/s")->capture_default_str();
  sim->add_option("--angular-speed", sim_opts->sim.angular_speed_deg_s, "RMS angular speed, deg/s")->capture_default_str();
  sim->add_option("--dropout", sim_opts->sim.dropout_rate, "Per LED and frame: probability a dropout starts")->capture_default_str()->check(CLI::Range(0.0, 1.0));
  sim->add_option("--stray", sim_opts->sim.stray_rate, "Per frame: probability a stray reflection appears")->capture_default_str()->check(CLI::Range(0.0, 1.0));
  sim_opts->cam.add_to(*sim);
  sim->callback([sim_opts] { run_simulate(*sim_opts); });

  auto solve_opts = std::make_shared<SolveOptions>();
  auto* solve = track.add_subcommand("solve", "Run the tracker on a Dots CSV; writes a Poses CSV and prints a summary");
  solve->add_option("--dots,-d", solve_opts->dots, "Dots CSV to read")->required();
  solve->add_option("--out,-o", solve_opts->out, "Poses CSV to write ('-' for stdout)");
  solve->add_option("--method", solve_opts->method, "Solver: lm (ours) or thesis (the 2009 reference)")->capture_default_str();
  solve->add_option("--filter", solve_opts->filter, "Filter: auto (eskf for lm, none for thesis), none, one-euro, median5, eskf (Kalman filter weighing each frame by its covariance)")->capture_default_str();
  solve->add_flag("--smooth", solve_opts->smooth,
                  "Offline: smooth the eskf's poses over the whole file (RTS: each pose also uses the frames after it); "
                  "stretches no head motion connects to the frames around them are written as lost");
  solve->add_option("--gate", solve_opts->gate_px, "Largest accepted RMS reprojection error, px")->capture_default_str()->check(CLI::PositiveNumber);
  solve_opts->cam.add_to(*solve);
  solve->callback([solve_opts] { run_solve(*solve_opts); });
  add_track_live_commands(track);
  add_track_calibrate_command(track);
  add_track_video_commands(track);
}

}  // namespace earshot::app
