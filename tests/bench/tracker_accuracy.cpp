// tracker_accuracy: every pose method on the same simulated walks, against
// ground truth. Prints markdown tables for docs/BENCHMARKS.md.
//
//   tracker_accuracy [--frames N] [--seed S]
//
// Methods: our tracker (lm, raw, with One Euro and with the eskf), the thesis
// method (its own labelling and median filter), OpenCV's solvePnP handed
// the TRUE labels (ITERATIVE from the previous pose; SQPNP + RefineLM), and
// the per-frame maximum-likelihood limit (LM started from the true pose).
// Errors are over frames where all four LEDs are seen.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "earshot/tracker/track/accuracy.hpp"
#include "earshot/tracker/track/dot_tracker.hpp"
#include "earshot/tracker/solve/lm_refine.hpp"
#include "earshot/tracker/sim/simulator.hpp"
#include "opencv_pnp.hpp"

using namespace earshot::tracker;
using earshot::PoseState;
using earshot::bench::CvMethod;
using earshot::bench::OpenCvPnp;

namespace {

struct Row {
  std::string name;
  TrackingTally tally;  // errors and flips over 4-dot frames
  bool tracks_all = true;  // false: only solves 4-dot frames with true labels
  double seconds = 0.0;
  long calls = 0;
};

LabelledDots true_labels(const DotFrame& f) {
  LabelledDots d;
  for (size_t s = 0; s < kSlots; ++s)
    if (f.truth->slot_led[s] > 0) d.add(f.truth->slot_led[s] - 1, *f.slots[s]);
  return d;
}

void account(Row& r, const DotFrame& f, bool tracked, const Pose& p) { r.tally.add(f, tracked, p); }

template <class F>
double timed(F&& fn, Row& r) {
  const auto t0 = std::chrono::steady_clock::now();
  fn();
  r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ++r.calls;
  return 0;
}

void run(PixelModel pixels, const char* label, long frames, std::uint64_t seed, bool upright = false) {
  const Camera cam = Camera::with_focal(1280);
  const LedModel model;
  SimulatorConfig cfg;
  cfg.seed = seed;
  cfg.pixels = pixels;
  if (upright) {  // the kind of walk the thesis's labelling was made for
    cfg.yaw_max_deg = 20;
    cfg.pitch_max_deg = 15;
    cfg.roll_max_deg = 10;
  }
  Simulator sim(cam, model, cfg);
  std::vector<DotFrame> walk;
  walk.reserve(static_cast<size_t>(frames));
  for (long i = 0; i < frames; ++i) walk.push_back(sim.next());

  std::vector<Row> rows(7);
  rows[0].name = "thesis (its labelling + median-5)";
  rows[1].name = "lm (ours, no filter)";
  rows[2].name = "lm + One Euro (ours)";
  rows[3].name = "OpenCV ITERATIVE, previous pose, true labels";
  rows[4].name = "OpenCV SQPNP + RefineLM, true labels";
  rows[5].name = "per-frame ML limit (LM from truth, true labels)";
  rows[6].name = "lm + eskf (ours, default)";
  for (size_t i = 3; i < 6; ++i) rows[i].tracks_all = false;

  TrackerConfig thesis_cfg;
  thesis_cfg.method = SolverMethod::thesis;
  TrackerConfig lm_cfg, lm_euro_cfg, lm_eskf_cfg;
  lm_euro_cfg.filter = FilterKind::one_euro;
  lm_eskf_cfg.filter = FilterKind::eskf;
  DotTracker thesis(cam, model, thesis_cfg), lm(cam, model, lm_cfg), lm_euro(cam, model, lm_euro_cfg),
      lm_eskf(cam, model, lm_eskf_cfg);
  OpenCvPnp cv_it(cam, model, CvMethod::iterative), cv_sq(cam, model, CvMethod::sqpnp_refine);

  for (const DotFrame& f : walk) {
    TrackResult r;
    timed([&] { r = thesis.process(f); }, rows[0]);
    account(rows[0], f, r.state == PoseState::tracking, r.pose);
    timed([&] { r = lm.process(f); }, rows[1]);
    account(rows[1], f, r.state == PoseState::tracking, r.pose);
    timed([&] { r = lm_euro.process(f); }, rows[2]);
    account(rows[2], f, r.state == PoseState::tracking, r.pose);
    timed([&] { r = lm_eskf.process(f); }, rows[6]);
    account(rows[6], f, r.state == PoseState::tracking, r.pose);
    if (leds_seen(f) != 4) {
      cv_it.reset();  // ITERATIVE restarts from SQPNP after a gap
      continue;
    }
    const LabelledDots d = true_labels(f);
    std::optional<Pose> p;
    timed([&] { p = cv_it.solve(d.view()); }, rows[3]);
    account(rows[3], f, p.has_value(), p.value_or(Pose{}));
    timed([&] { p = cv_sq.solve(d.view()); }, rows[4]);
    account(rows[4], f, p.has_value(), p.value_or(Pose{}));
    LmResult ml;
    timed([&] { ml = refine_pose_lm(f.truth->pose, d.view(), cam, model); }, rows[5]);
    account(rows[5], f, true, ml.pose);
  }

  std::printf("\n### %ld-frame walk, seed %llu, f = 1280 px, %s\n\n", frames,
              static_cast<unsigned long long>(seed), label);
  std::printf("| method | tracked of 3+ dot frames | rot RMS (deg) | rot p95 | trans RMS (mm) | trans p95 | flipped 4-dot frames | us/frame |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const auto rot = r.tally.four_dot.rotation_deg(), tr = r.tally.four_dot.translation_mm();
    char tracked[64];
    if (r.tracks_all)
      std::snprintf(tracked, sizeof tracked, "%.3f %%", 100.0 * static_cast<double>(r.tally.tracked_3plus) / static_cast<double>(r.tally.frames_3plus));
    else
      std::snprintf(tracked, sizeof tracked, "4-dot frames only");
    std::printf("| %s | %s | %.3f | %.3f | %.2f | %.2f | %ld | %.2f |\n", r.name.c_str(), tracked, rot.rms, rot.p95,
                tr.rms, tr.p95, r.tally.flips_4dot, r.calls ? 1e6 * r.seconds / static_cast<double>(r.calls) : 0.0);
  }
  const double best_cv = std::min(rows[3].tally.four_dot.rotation_deg().rms, rows[4].tally.four_dot.rotation_deg().rms);
  const double best_cv_t = std::min(rows[3].tally.four_dot.translation_mm().rms, rows[4].tally.four_dot.translation_mm().rms);
  const double ml_r = rows[5].tally.four_dot.rotation_deg().rms, ml_t = rows[5].tally.four_dot.translation_mm().rms;
  std::printf("\nlm / best OpenCV: rotation %.3f, translation %.3f; lm / ML limit: rotation %.3f, translation %.3f; "
              "lm + One Euro / ML limit: rotation %.3f, translation %.3f; lm + eskf / ML limit: rotation %.3f, translation %.3f\n",
              rows[1].tally.four_dot.rotation_deg().rms / best_cv, rows[1].tally.four_dot.translation_mm().rms / best_cv_t,
              rows[1].tally.four_dot.rotation_deg().rms / ml_r, rows[1].tally.four_dot.translation_mm().rms / ml_t,
              rows[2].tally.four_dot.rotation_deg().rms / ml_r, rows[2].tally.four_dot.translation_mm().rms / ml_t,
              rows[6].tally.four_dot.rotation_deg().rms / ml_r, rows[6].tally.four_dot.translation_mm().rms / ml_t);
}

/// Latency of each filter on a head turning at a constant rate, and its
/// effect on a still head's jitter: the lag is the angle it trails by
/// divided by the angular speed.
void filter_latency() {
  std::printf("\n### Filter latency (100 Hz frames)\n\n");
  std::printf("| filter | lag at 30 deg/s (ms) | lag at 90 deg/s (ms) | lag at 270 deg/s (ms) | still head: jitter kept (%% of raw RMS) |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const char* name : {"none", "one-euro", "median5"}) {
    const auto kind = filter_kind_from(name).value();
    auto make = [&]() {
      return [kind, euro = PoseOneEuro(), med = MedianPoseFilter()](const Pose& p, double t) mutable {
        return kind == FilterKind::one_euro ? euro.filter(p, t) : kind == FilterKind::median5 ? med.filter(p) : p;
      };
    };
    std::printf("| %s |", name);
    for (double deg_s : {30.0, 90.0, 270.0}) {
      auto f = make();
      const double w = deg_s * M_PI / 180.0;
      double lag = 0.0;
      for (int i = 0; i < 200; ++i) {
        const double t = i * 0.01;
        const Pose p{rotation_from_ypr(w * t, 0, 0), Vec3(0, 0, 1000)};
        const Pose out = f(p, t);
        if (i == 199) lag = rotation_angle_between(out.R, p.R) / w;
      }
      std::printf(" %.1f |", 1000.0 * lag);
    }
    auto f = make();
    std::mt19937_64 rng(1);
    std::normal_distribution<double> n(0.0, 0.01);  // about 0.6 deg of jitter per axis
    double raw = 0, kept = 0;
    for (int i = 0; i < 3000; ++i) {
      const Pose p{exp_so3(Vec3(n(rng), n(rng), n(rng))), Vec3(0, 0, 1000)};
      const Pose out = f(p, i * 0.01);
      if (i < 100) continue;
      raw += log_so3(p.R).squaredNorm();
      kept += log_so3(out.R).squaredNorm();
    }
    std::printf(" %.0f %% |\n", 100.0 * std::sqrt(kept / raw));
  }
}

}  // namespace

int main(int argc, char** argv) {
  long frames = 10000;
  std::uint64_t seed = 1;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) {
      frames = std::atol(argv[++i]);
    } else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else {
      std::fprintf(stderr, "usage: tracker_accuracy [--frames N] [--seed S]\n");
      return 2;
    }
  }
  if (frames <= 0) {
    std::fprintf(stderr, "tracker_accuracy: --frames must be positive\n");
    return 2;
  }
  run(PixelModel::integer, "integer pixels", frames, seed);
  run(PixelModel::quantize8, "8-px quantisation (thesis)", frames, seed);
  run(PixelModel::integer, "integer pixels, upright walk (yaw 20, pitch 15, roll 10 deg)", frames, seed, true);
  filter_latency();
  return 0;
}
