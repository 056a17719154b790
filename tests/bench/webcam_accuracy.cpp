// webcam_accuracy: the webcam beacons end to end on synthetic video, against
// ground truth and the per-frame ML limit. Prints markdown tables for
// docs/BENCHMARKS.md.
//
//   webcam_accuracy [--frames N] [--seeds heldout|tuning|S] [--beacon leds|apriltag|both] [--decimate D]
//   webcam_accuracy --listener [--frames N] [--seeds ...] [--decimate D]
//
// --decimate sets the tag detector's quad_decimate (1 by default; 2 halves
// the segmentation's resolution, the corners are still refined at full).
// Each run renders a head walk (VideoSimulator: noise, motion blur,
// auto-exposure drift, 60-degree horizontal field of view, 30 frames/s,
// 1/60 s exposure), detects the beacon in every frame and solves the pose:
//   leds      the thesis beacon; the LED detector's unlabelled dots through
//             the tracker's normal path (DotTracker: labeller + LM, no filter);
//   apriltag  an 80 mm tag36h11 (id 0) centred where the LED beacon's centre
//             is (on the headphones' band, facing the camera at the identity
//             pose); its labelled corners straight into the LM solver (from
//             the previous frame's pose, else P3P), model tag_corners_mm(80).
// Errors are over frames whose four points are all in view. The ML limit:
// LM from the true pose on the true projections plus Gaussian noise of the
// dot error this run measured (per axis), i.e. what any per-frame solver
// could reach from dots as good as the detector's.
// --listener: the tag path as the listener hears it, the detected corners
// through LabelledTracker (the live tag path after its detector), scored as
// tracker_motion --listener scores a walk (listener_scores.hpp: raw LM, the
// default, --smooth and holding the last pose).
// Seeds: held-out 1001-1003 (nothing in the detectors or the renderer was
// tuned on them); the unit tests use seed 1.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "earshot/tracker/track/accuracy.hpp"
#include "earshot/tracker/track/dot_tracker.hpp"
#include "earshot/tracker/solve/lm_refine.hpp"
#include "earshot/tracker/solve/lm_solver.hpp"
#include "earshot/webcam/dot_detector.hpp"
#include "earshot/webcam/video_sim.hpp"
#include "listener_scores.hpp"

using namespace earshot::tracker;
using namespace earshot::webcam;
using earshot::PoseState;

// Costs are this thread's CPU time (the machine may be shared: wall time
// would count other processes' turns).
struct clk {
  using duration = std::chrono::nanoseconds;
  using time_point = std::chrono::time_point<clk, duration>;
  static time_point now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return time_point(duration(static_cast<long long>(ts.tv_sec) * 1000000000LL + ts.tv_nsec));
  }
};

namespace {

struct Options {
  long frames = 300;
  std::vector<std::uint64_t> seeds{1001, 1002, 1003};
  bool leds = true, tag = true;
  float decimate = 1.0f;  ///< the tag detector's quad_decimate
  bool listener = false;  ///< the tag path on the listener's terms
};

struct Stored {
  Pose truth;
  std::array<Vec2, 4> points;
};

double ms(clk::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

void run(const Options& o, BeaconKind beacon, int width, int height, MotionProfile motion) {
  AccuracyCollector err, ml;
  long eligible = 0, found = 0, tracked = 0;
  double dot_sum2 = 0.0;
  long dot_n = 0;
  std::vector<double> detect_ms, solve_ms;
  std::vector<Stored> stored;
  Camera cam;
  LedModel model;
  for (const auto seed : o.seeds) {
    VideoSimConfig cfg;
    cfg.beacon = beacon;
    cfg.width = width;
    cfg.height = height;
    cfg.motion = motion;
    cfg.seed = seed;
    VideoSimulator sim(cfg);
    cam = sim.camera();
    model = sim.model();
    AprilTagOptions tag_options;
    tag_options.decimate = o.decimate;
    auto det = beacon == BeaconKind::leds ? make_led_detector() : make_apriltag_detector(tag_options);
    DotTracker tracker(cam, model);
    LmSolver solver(cam, model);
    std::optional<Pose> last;
    VideoFrame f;
    for (long i = 0; i < o.frames; ++i) {
      sim.next(f);
      const auto t0 = clk::now();
      const Detection d = det->detect(f.view(width, height));
      const auto t1 = clk::now();
      detect_ms.push_back(ms(t1 - t0));
      bool ok = false;
      Pose pose;
      clk::duration solve{};
      if (beacon == BeaconKind::leds) {
        DotFrame df;
        df.t = f.t;
        for (int k = 0; k < d.count; ++k)
          df.slots[static_cast<size_t>(k)] = Vec2(d.points[static_cast<size_t>(k)].x, d.points[static_cast<size_t>(k)].y);
        const auto s0 = clk::now();
        const TrackResult r = tracker.process(df);
        solve = clk::now() - s0;
        ok = r.state == PoseState::tracking;
        pose = r.pose;
      } else if (d.count == 4) {
        LabelledDots dots;
        for (int k = 0; k < 4; ++k)
          dots.add(k, Vec2(d.points[static_cast<size_t>(k)].x, d.points[static_cast<size_t>(k)].y));
        const auto s0 = clk::now();
        const std::optional<Pose> p = solver.solve({dots.view(), last ? &*last : nullptr});
        solve = clk::now() - s0;
        if (p) {
          ok = true;
          pose = *p;
        }
      }
      last = ok ? std::optional<Pose>(pose) : std::nullopt;
      if (beacon == BeaconKind::apriltag && d.count == 4) solve_ms.push_back(ms(solve));
      if (beacon == BeaconKind::leds) solve_ms.push_back(ms(solve));

      const bool all_in_view = std::all_of(f.points.begin(), f.points.end(), [](const auto& p) { return p.has_value(); });
      if (!all_in_view) continue;
      ++eligible;
      Stored s{f.truth, {*f.points[0], *f.points[1], *f.points[2], *f.points[3]}};
      stored.push_back(s);
      if (d.count == 4) {
        ++found;
        for (size_t k = 0; k < 4; ++k) {
          const Vec2 p(d.points[k].x, d.points[k].y);
          Vec2 truth = s.points[k];
          if (!d.labelled)
            for (const Vec2& q : s.points)
              if ((q - p).norm() < (truth - p).norm()) truth = q;
          dot_sum2 += (p - truth).squaredNorm();
          ++dot_n;
        }
      }
      if (ok) {
        ++tracked;
        err.add(pose, f.truth);
      }
    }
  }
  const double dot_rms = dot_n ? std::sqrt(dot_sum2 / static_cast<double>(dot_n)) : 0.0;
  // The ML limit at the measured dot noise (per axis: rms / sqrt 2).
  std::mt19937_64 rng(99);
  std::normal_distribution<double> noise(0.0, dot_rms / std::sqrt(2.0));
  for (const Stored& s : stored) {
    LabelledDots dots;
    for (int k = 0; k < 4; ++k)
      dots.add(k, s.points[static_cast<size_t>(k)] + Vec2(noise(rng), noise(rng)));
    ml.add(refine_pose_lm(s.truth, dots.view(), cam, model).pose, s.truth);
  }
  auto mean = [](const std::vector<double>& v) {
    double a = 0.0;
    for (double x : v) a += x;
    return v.empty() ? 0.0 : a / static_cast<double>(v.size());
  };
  auto pct = [](long a, long b) { return b ? 100.0 * static_cast<double>(a) / static_cast<double>(b) : 0.0; };
  const ErrorStats r = err.rotation_deg(), t = err.translation_mm();
  const ErrorStats mr = ml.rotation_deg(), mt = ml.translation_mm();
  std::printf("| %s | %dx%d | %s | %ld | %.1f | %.1f | %.3f | %.3f | %.3f | %.2f | %.2f | %.3f | %.2f | %.2f | %.2f | %.2f | %.3f |\n",
              beacon == BeaconKind::leds ? "LEDs (thesis)" : "tag36h11 80 mm", width, height,
              std::string(motion_profile_name(motion)).c_str(), eligible, pct(found, eligible), pct(tracked, eligible),
              dot_rms, r.rms, r.p95, t.rms, t.p95, mr.rms, mt.rms, mr.rms > 0 ? r.rms / mr.rms : 0.0,
              mt.rms > 0 ? t.rms / mt.rms : 0.0, mean(detect_ms), mean(solve_ms));
  std::fflush(stdout);
}

/// The tag's detected corners per frame, labelled (slot k is corner k), with
/// the truth, through listener_scores.hpp.
void run_listener(const Options& o, int width, int height, MotionProfile motion) {
  bench::WalkScores all;
  for (const auto seed : o.seeds) {
    VideoSimConfig cfg;
    cfg.beacon = BeaconKind::apriltag;
    cfg.width = width;
    cfg.height = height;
    cfg.motion = motion;
    cfg.seed = seed;
    VideoSimulator sim(cfg);
    AprilTagOptions tag_options;
    tag_options.decimate = o.decimate;
    auto det = make_apriltag_detector(tag_options);
    std::vector<DotFrame> walk;
    VideoFrame f;
    for (long i = 0; i < o.frames; ++i) {
      sim.next(f);
      const Detection d = det->detect(f.view(width, height));
      DotFrame df;
      df.t = f.t;
      GroundTruth gt;
      gt.pose = f.truth;
      if (d.count == 4)
        for (size_t k = 0; k < 4; ++k) {
          df.slots[k] = Vec2(d.points[k].x, d.points[k].y);
          gt.slot_led[k] = static_cast<int>(k) + 1;
        }
      df.truth = gt;
      walk.push_back(df);
    }
    all.merge(bench::score_walk(sim.camera(), sim.model(), walk, true));
  }
  bench::print_row("tag36h11 80 mm, " + std::to_string(width) + "x" + std::to_string(height) + ", " +
                       std::string(motion_profile_name(motion)),
                   all);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "webcam_accuracy: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--frames") {
      o.frames = std::atol(value().c_str());
    } else if (a == "--seeds") {
      const std::string s = value();
      if (s == "heldout") o.seeds = {1001, 1002, 1003};
      else if (s == "tuning") o.seeds = {1, 2, 3};
      else o.seeds = {std::strtoull(s.c_str(), nullptr, 10)};
    } else if (a == "--decimate") {
      o.decimate = static_cast<float>(std::atof(value().c_str()));
    } else if (a == "--listener") {
      o.listener = true;
    } else if (a == "--beacon") {
      const std::string b = value();
      o.leds = b == "leds" || b == "both";
      o.tag = b == "apriltag" || b == "both";
    } else {
      std::fprintf(stderr, "usage: webcam_accuracy [--listener] [--frames N] [--seeds heldout|tuning|S] [--beacon leds|apriltag|both] [--decimate D]\n");
      return 2;
    }
  }
  if (o.frames <= 0 || (!o.leds && !o.tag)) {
    std::fprintf(stderr, "webcam_accuracy: nothing to run\n");
    return 2;
  }
  if (o.listener) {
    std::printf("Synthetic webcam video of an 80 mm tag, %ld frames x %zu seeds per row, tag decimate %g; the corners through LabelledTracker\n\n",
                o.frames, o.seeds.size(), static_cast<double>(o.decimate));
    bench::print_header();
    for (const auto& res : {std::array<int, 2>{640, 480}, std::array<int, 2>{1280, 720}})
      for (const MotionProfile m : {MotionProfile::seated, MotionProfile::orienting}) run_listener(o, res[0], res[1], m);
    return 0;
  }
  std::printf("Synthetic webcam video, %ld frames x %zu seeds per row (30 frames/s, 60 deg horizontal FOV, 1/60 s exposure), "
              "tag decimate %g\n\n", o.frames, o.seeds.size(), static_cast<double>(o.decimate));
  std::printf("| beacon | camera | motion | 4-point frames | found %% | tracked %% | dot RMS (px) | rot RMS (deg) | rot p95 | "
              "trans RMS (mm) | trans p95 | ML rot RMS | ML trans RMS | rot / ML | trans / ML | detect (ms CPU) | solve (ms CPU) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const BeaconKind b : {BeaconKind::leds, BeaconKind::apriltag}) {
    if ((b == BeaconKind::leds && !o.leds) || (b == BeaconKind::apriltag && !o.tag)) continue;
    for (const auto& res : {std::array<int, 2>{640, 480}, std::array<int, 2>{1280, 720}})
      for (const MotionProfile m : {MotionProfile::seated, MotionProfile::orienting}) run(o, b, res[0], res[1], m);
  }
  return 0;
}
