#include "earshot/tracker/accuracy.hpp"

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
  std::sort(v.begin(), v.end());
  s.max = v.back();
  const size_t k = static_cast<size_t>(std::ceil(0.95 * static_cast<double>(v.size()))) - 1;
  s.p95 = v[std::min(k, v.size() - 1)];
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
  const int leds = leds_seen(f);
  if (leds >= 3) {
    ++frames_3plus;
    tracked_3plus += tracked ? 1 : 0;
  }
  if (!tracked || !f.truth) return;
  const bool flip = rotation_angle_between(estimate.R, f.truth->pose.R) > kFlipDeg * std::numbers::pi / 180.0;
  all.add(estimate, f.truth->pose);
  flips += flip ? 1 : 0;
  if (leds == 4) {
    four_dot.add(estimate, f.truth->pose);
    flips_4dot += flip ? 1 : 0;
  }
}

}  // namespace earshot::tracker
