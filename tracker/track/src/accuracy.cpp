#include "earshot/tracker/track/accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace earshot::tracker {

ErrorStats error_stats(std::vector<double> v) {
  ErrorStats s;
  s.count = v.size();
  if (v.empty()) return s;
  double sum = 0.0, sum2 = 0.0;
  for (double x : v) {
    sum += x;
    sum2 += x * x;
  }
  s.mean = sum / static_cast<double>(v.size());
  s.rms = std::sqrt(sum2 / static_cast<double>(v.size()));
  s.max = *std::max_element(v.begin(), v.end());
  // The p95 element where a full sort would put it, in linear time.
  const size_t k = std::min(static_cast<size_t>(std::ceil(0.95 * static_cast<double>(v.size()))) - 1, v.size() - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  s.p95 = v[k];
  return s;
}

void AccuracyCollector::add(const Pose& estimate, const Pose& truth) {
  rot_deg_.push_back(rotation_angle_between(estimate.R, truth.R) * 180.0 / std::numbers::pi);
  trans_mm_.push_back((estimate.t - truth.t).norm());
}

}  // namespace earshot::tracker

namespace earshot::tracker {

int leds_seen(const DotFrame& f) {
  if (!f.truth) return f.visible();
  int n = 0;
  for (int l : f.truth->slot_led) n += l > 0 ? 1 : 0;
  return n;
}

void TrackingTally::add(const DotFrame& f, bool tracked, const Pose& estimate) {
  add(leds_seen(f), f.truth ? std::optional<Pose>(f.truth->pose) : std::nullopt, tracked, estimate);
}

void TrackingTally::add(int leds, const std::optional<Pose>& truth, bool tracked, const Pose& estimate) {
  if (leds >= 3) {
    ++frames_3plus;
    tracked_3plus += tracked ? 1 : 0;
  }
  if (!tracked || !truth) return;
  const bool flip = rotation_angle_between(estimate.R, truth->R) > kFlipDeg * std::numbers::pi / 180.0;
  all.add(estimate, *truth);
  flips += flip ? 1 : 0;
  if (leds == 4) {
    four_dot.add(estimate, *truth);
    flips_4dot += flip ? 1 : 0;
  }
}

}  // namespace earshot::tracker
