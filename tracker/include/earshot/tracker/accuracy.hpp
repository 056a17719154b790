// Accuracy statistics of estimated poses against ground truth.
#pragma once

#include <vector>

#include "earshot/tracker/geometry.hpp"

namespace earshot::tracker {

struct ErrorStats {
  size_t count = 0;
  double rms = 0.0, p95 = 0.0, max = 0.0, mean = 0.0;
};

[[nodiscard]] ErrorStats error_stats(std::vector<double> values);

/// Collects rotation (degrees) and translation (mm) errors frame by frame.
class AccuracyCollector {
 public:
  void add(const Pose& estimate, const Pose& truth);
  [[nodiscard]] ErrorStats rotation_deg() const { return error_stats(rot_deg_); }
  [[nodiscard]] ErrorStats translation_mm() const { return error_stats(trans_mm_); }
  [[nodiscard]] size_t count() const { return rot_deg_.size(); }

 private:
  std::vector<double> rot_deg_, trans_mm_;
};

}  // namespace earshot::tracker
