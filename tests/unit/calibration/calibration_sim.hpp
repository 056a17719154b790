// Simulated calibration sessions, shared by the calibration tests and the
// led_calibration benchmark: a rig whose model is off by a few mm, a seated
// recording of it, and tracking error on a held-out walk with a given model.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "earshot/tracker/track/accuracy.hpp"
#include "earshot/tracker/track/dot_tracker.hpp"
#include "earshot/tracker/calibration/led_calibration.hpp"
#include "earshot/tracker/sim/simulator.hpp"

namespace calibration_sim {

using namespace earshot::tracker;

/// `truth` with every LED moved `mm` in a random direction.
inline LedModel perturbed(const LedModel& truth, double mm, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  LedModel m = truth;
  for (auto& p : m.leds_mm) {
    Vec3 d(n(rng), n(rng), n(rng));
    p += mm * d.normalized();
  }
  return m;
}

/// A recording of `frames` frames at 100 Hz (integer pixels unless told).
inline std::vector<DotFrame> session(const Camera& cam, const LedModel& truth, MotionProfile motion,
                                     std::uint64_t seed, int frames, PixelModel pixels = PixelModel::integer) {
  SimulatorConfig cfg;
  cfg.motion = motion;
  cfg.seed = seed;
  cfg.pixels = pixels;
  Simulator sim(cam, truth, cfg);
  std::vector<DotFrame> out;
  out.reserve(static_cast<size_t>(frames));
  for (int i = 0; i < frames; ++i) out.push_back(sim.next());
  return out;
}

/// Raw LM tracking error of `model` on frames simulated with `truth`. The
/// model's frame differs from the truth's by a constant rigid motion (the
/// calibration's free gauge, which recentering removes in use): each pose is
/// composed with the rigid alignment of the true LEDs onto the model's.
struct TrackingError {
  double rot_rms_deg = 0.0, trans_rms_mm = 0.0;
  double trans_centred_rms_mm = 0.0;  ///< with the mean translation error removed
  size_t frames = 0;
};

inline TrackingError tracking_error(const std::vector<DotFrame>& frames, const Camera& cam, const LedModel& model,
                                    const LedModel& truth) {
  TrackerConfig cfg;
  cfg.filter = FilterKind::none;
  DotTracker tracker(cam, model, cfg);
  const Pose a = rigid_align(truth.leds_mm, model.leds_mm);  // true frame -> model frame
  AccuracyCollector acc;
  std::vector<Vec3> dt;
  for (const DotFrame& f : frames) {
    const TrackResult r = tracker.process(f);
    if (r.state != earshot::PoseState::tracking || leds_seen(f) != 4) continue;
    Pose p;
    p.R = r.raw_pose.R * a.R;
    p.t = r.raw_pose.R * a.t + r.raw_pose.t;
    acc.add(p, f.truth->pose);
    dt.push_back(p.t - f.truth->pose.t);
  }
  Vec3 mean = Vec3::Zero();
  for (const Vec3& d : dt) mean += d / static_cast<double>(dt.size());
  double ss = 0.0;
  for (const Vec3& d : dt) ss += (d - mean).squaredNorm();
  const double centred = dt.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(dt.size()));
  return {acc.rotation_deg().rms, acc.translation_mm().rms, centred, acc.count()};
}

inline double max_of(const std::array<double, 4>& v) { return std::max(std::max(v[0], v[1]), std::max(v[2], v[3])); }

}  // namespace calibration_sim
