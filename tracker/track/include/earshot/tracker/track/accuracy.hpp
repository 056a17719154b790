// Accuracy statistics of estimated poses against ground truth, and the
// tally of a tracking run over simulated frames (what `earshot track solve`
// prints and the tracker_accuracy benchmark tabulates).
#pragma once

#include <vector>

#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/geometry.hpp"

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

/// LEDs in view: per ground truth when the frame has it (a stray reflection
/// is not an LED), else the dots seen.
[[nodiscard]] int leds_seen(const DotFrame& f);

/// A tracked pose this far (degrees) from the truth counts as a flip.
inline constexpr double kFlipDeg = 20.0;

/// How a run tracked the frames it was given, judged against ground truth
/// where the frame carries it.
struct TrackingTally {
  long frames_3plus = 0, tracked_3plus = 0;  ///< frames with >= 3 LEDs seen, and those tracked
  AccuracyCollector all, four_dot;           ///< errors of tracked frames: all, and with 4 LEDs seen
  long flips = 0, flips_4dot = 0;            ///< tracked frames beyond kFlipDeg: all, and with 4 LEDs

  /// One frame: `tracked` says whether `estimate` is a tracked pose.
  void add(const DotFrame& f, bool tracked, const Pose& estimate);
  /// The same from what it uses of the frame: LEDs seen (leds_seen) and the
  /// true pose when known.
  void add(int leds, const std::optional<Pose>& truth, bool tracked, const Pose& estimate);
};

}  // namespace earshot::tracker
