// tracker_bench: per-frame cost of label + solve + filter, beside OpenCV's
// solvePnP on the same frames (given the true labels, so it does less work);
// and the parts alone: the LM solve, the eskf's update (with the pose
// covariance) and the RTS smoother, per frame.
//   tracker_bench [--benchmark_min_time=0.5]
#include <benchmark/benchmark.h>

#include <vector>

#include "earshot/tracker/track/dot_tracker.hpp"
#include "earshot/tracker/filter/eskf.hpp"
#include "earshot/tracker/track/labeller.hpp"
#include "earshot/tracker/solve/lm_solver.hpp"
#include "earshot/tracker/solve/p3p.hpp"
#include "earshot/tracker/sim/simulator.hpp"
#include "opencv_pnp.hpp"

using namespace earshot::tracker;
using earshot::bench::CvMethod;
using earshot::bench::OpenCvPnp;

namespace {

const Camera kCam = Camera::with_focal(1280);
const LedModel kModel;

/// A 10,000-frame integer-pixel walk (seed 1), simulated once.
const std::vector<DotFrame>& walk() {
  static const std::vector<DotFrame> frames = [] {
    Simulator sim(kCam, kModel, {});
    std::vector<DotFrame> v;
    for (int i = 0; i < 10000; ++i) v.push_back(sim.next());
    return v;
  }();
  return frames;
}

/// The frames with all four LEDs seen, with their true labels.
const std::vector<LabelledDots>& four_dot_frames() {
  static const std::vector<LabelledDots> frames = [] {
    std::vector<LabelledDots> v;
    for (const auto& f : walk()) {
      LabelledDots d;
      for (size_t s = 0; s < kSlots; ++s)
        if (f.truth->slot_led[s] > 0) d.add(f.truth->slot_led[s] - 1, *f.slots[s]);
      if (d.count == 4) v.push_back(d);
    }
    return v;
  }();
  return frames;
}

void run_tracker(benchmark::State& state, TrackerConfig cfg) {
  const auto& frames = walk();
  DotTracker tracker(kCam, kModel, cfg);
  size_t i = 0;
  for (auto _ : state) {
    if (i == frames.size()) {
      i = 0;
      tracker.reset();
    }
    benchmark::DoNotOptimize(tracker.process(frames[i++]));
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_lm(benchmark::State& state) {
  TrackerConfig cfg;
  cfg.filter = FilterKind::one_euro;
  run_tracker(state, cfg);
}
void BM_lm_no_filter(benchmark::State& state) { run_tracker(state, {}); }
void BM_thesis(benchmark::State& state) {
  TrackerConfig cfg;
  cfg.method = SolverMethod::thesis;
  run_tracker(state, cfg);
}

void run_cv(benchmark::State& state, CvMethod m) {
  const auto& frames = four_dot_frames();
  OpenCvPnp pnp(kCam, kModel, m);
  size_t i = 0;
  for (auto _ : state) {
    if (i == frames.size()) i = 0;
    benchmark::DoNotOptimize(pnp.solve(frames[i++].view()));
  }
  state.SetItemsProcessed(state.iterations());
}
void BM_cv_iterative(benchmark::State& state) { run_cv(state, CvMethod::iterative); }
void BM_cv_sqpnp_refine(benchmark::State& state) { run_cv(state, CvMethod::sqpnp_refine); }

void BM_lm_eskf(benchmark::State& state) {
  TrackerConfig cfg;
  cfg.filter = FilterKind::eskf;
  run_tracker(state, cfg);
}

/// The walk's raw LM poses with their covariances, solved once: what the
/// filter and the smoother are fed, so their benchmarks time them alone.
struct Measured {
  double t;
  Pose pose;
  Mat6 cov;
};
const std::vector<Measured>& measured() {
  static const std::vector<Measured> v = [] {
    std::vector<Measured> out;
    DotTracker tracker(kCam, kModel, {});
    for (const auto& f : walk()) {
      const TrackResult r = tracker.process(f);
      if (r.state != earshot::PoseState::tracking) continue;
      LabelledDots d;
      for (size_t s = 0; s < kSlots; ++s)
        if (r.slot_led[s] >= 0 && f.slots[s]) d.add(r.slot_led[s], *f.slots[s]);
      out.push_back({r.t, r.raw_pose, pose_covariance(r.raw_pose, d.view(), kCam, kModel, 1.0 / 12.0)});
    }
    return out;
  }();
  return v;
}

/// The solver alone: LM from the previous frame's pose, true labels, 4 dots.
void BM_lm_solve(benchmark::State& state) {
  const auto& frames = four_dot_frames();
  LmSolver solver(kCam, kModel);
  std::optional<Pose> prev;
  size_t i = 0;
  for (auto _ : state) {
    if (i == frames.size()) i = 0;
    const auto p = solver.solve({frames[i++].view(), prev ? &*prev : nullptr});
    if (p) prev = p;
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(state.iterations());
}

/// The eskf's per-frame work: the pose covariance from the dots, then the
/// update (prediction, manoeuvre test, gain, covariance).
void BM_eskf_update(benchmark::State& state) {
  const auto& m = measured();
  const auto& frames = four_dot_frames();
  PoseEskf eskf;
  size_t i = 0;
  double t0 = 0.0;
  for (auto _ : state) {
    if (i == m.size()) {
      i = 0;
      t0 += m.back().t + 1.0;  // time runs on: no restart from a gap backwards
    }
    const Mat6 cov = pose_covariance(m[i].pose, frames[i % frames.size()].view(), kCam, kModel, 1.0 / 12.0);
    benchmark::DoNotOptimize(cov);
    benchmark::DoNotOptimize(eskf.update(m[i].pose, m[i].cov, t0 + m[i].t));
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}

/// The offline smoother per frame: recording the step (its gain) as the
/// filter runs, and the backward pass, over the whole walk.
void BM_rts_smooth(benchmark::State& state) {
  const auto& m = measured();
  std::vector<EskfStep> steps;
  PoseEskf eskf;
  for (const auto& x : m) {
    eskf.update(x.pose, x.cov, x.t);
    steps.push_back(eskf.last_step());
  }
  for (auto _ : state) {
    RtsSmoother s;
    s.reserve(steps.size());
    for (const auto& st : steps) s.add(st);
    benchmark::DoNotOptimize(s.smooth());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(steps.size()));
}

void BM_lm_acquire(benchmark::State& state) {
  const Labeller labeller(kCam, kModel);
  const DotFrame& f = walk().front();
  for (auto _ : state) benchmark::DoNotOptimize(labeller.acquire(f));
}

void BM_p3p(benchmark::State& state) {
  const Pose p{rotation_from_ypr(0.3, -0.2, 1.0), Vec3(30, -20, 1100)};
  std::array<Vec3, 3> y, x;
  for (size_t k = 0; k < 3; ++k) {
    x[k] = kModel.leds_mm[k];
    y[k] = p.apply(x[k]).normalized();
  }
  for (auto _ : state) benchmark::DoNotOptimize(p3p_lambda_twist(y, x));
}

}  // namespace

BENCHMARK(BM_lm);
BENCHMARK(BM_lm_no_filter);
BENCHMARK(BM_lm_eskf);
BENCHMARK(BM_lm_solve);
BENCHMARK(BM_eskf_update);
BENCHMARK(BM_rts_smooth);
BENCHMARK(BM_thesis);
BENCHMARK(BM_cv_iterative);
BENCHMARK(BM_cv_sqpnp_refine);
BENCHMARK(BM_lm_acquire);
BENCHMARK(BM_p3p);
BENCHMARK_MAIN();
