// Jitter filters and prediction for poses.
//
//  OneEuroFilter       Casiez et al. 2012: a low-pass whose cutoff rises with
//                      speed, so it smooths a still head and lags little
//                      when it moves. Used on position and on rotation.
//  MedianPoseFilter    the thesis's median of 5 (two frames of delay), kept
//                      for comparison.
//  ConstantVelocity    extrapolates the last two poses to a requested time.
// Latencies measured by tests/bench (see docs/BENCHMARKS.md).
#pragma once

#include <array>
#include <optional>

#include "earshot/tracker/core/geometry.hpp"

namespace earshot::tracker {

struct OneEuroParams {
  double min_cutoff_hz = 1.0;
  double beta = 0.05;         ///< cutoff increase per unit of speed
  double derivative_cutoff_hz = 1.0;
};

/// One Euro filter on a vector of N values.
template <int N>
class OneEuroFilter {
 public:
  using Vec = Eigen::Matrix<double, N, 1>;
  explicit OneEuroFilter(OneEuroParams p = {}) : p_(p) {}

  Vec filter(const Vec& x, double t);
  void reset() { have_ = false; }
  /// Moves the filtered value by `delta` (keeps the speed estimate): used
  /// when the caller re-expresses the value in a new reference.
  void shift(const Vec& delta) { x_prev_ += delta; }

 private:
  static double alpha(double cutoff, double dt);
  OneEuroParams p_;
  Vec x_prev_ = Vec::Zero();
  Vec dx_prev_ = Vec::Zero();
  double t_prev_ = 0.0;
  bool have_ = false;
};

/// One Euro on a pose: translation (mm) and rotation (as the rotation vector
/// relative to a reference that is moved to the output whenever they drift
/// apart, so the filtered vector stays small and never wraps at pi).
class PoseOneEuro {
 public:
  /// Defaults tuned on simulated walks (tests/bench/tracker_accuracy).
  explicit PoseOneEuro(OneEuroParams translation = {0.5, 0.1, 1.0},
                       OneEuroParams rotation = {2.0, 20.0, 1.0});
  Pose filter(const Pose& p, double t);
  void reset();

 private:
  OneEuroFilter<3> trans_;
  OneEuroFilter<3> rot_;
  Mat3 R_ref_ = Mat3::Identity();
  bool have_ = false;
};

/// Median of the last five poses, per translation axis and per rotation-vector
/// component relative to the newest pose. Adds two frames of delay.
class MedianPoseFilter {
 public:
  Pose filter(const Pose& p);
  void reset() { n_ = 0; }

 private:
  std::array<Pose, 5> ring_{};
  int n_ = 0;
  int head_ = 0;
};

/// Constant-velocity prediction from the last two poses.
class ConstantVelocity {
 public:
  void observe(const Pose& p, double t);
  /// The pose extrapolated to time t (the last pose when only one is known).
  [[nodiscard]] std::optional<Pose> predict(double t) const;
  void reset() { n_ = 0; }
  [[nodiscard]] double last_time() const { return t1_; }

 private:
  Pose p0_, p1_;
  double t0_ = 0.0, t1_ = 0.0;
  int n_ = 0;
};

}  // namespace earshot::tracker

#include "earshot/tracker/filter/filters_impl.hpp"
