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
