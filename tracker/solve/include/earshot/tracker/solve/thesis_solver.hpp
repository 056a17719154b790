// The thesis's P4P method (Yashar, 2009, section 3.2), kept as the reference:
//  1. ray angles from the four image points (eq. 47);
//  2. camera-LED distances r_1..r_4 from the six law-of-cosines equations
//     (eq. 48) by Gauss-Newton, started from the previous frame's result;
//  3. a median-of-5 filter on the distances (section 3.2.9; 2 frames latency);
//  4. 3D LED positions along the rays (eq. 49);
//  5. absolute orientation by SVD (eq. 50-56).
// Note: eq. 48 as printed omits the factor 2 of the law of cosines
// (r_i^2 + r_j^2 - 2 r_i r_j cos(theta_ij) = d_ij^2); we use the correct law.
// Needs all four LEDs: the thesis drops frames with fewer.
#pragma once

#include <array>
#include <deque>

#include "earshot/tracker/solve/solver.hpp"

namespace earshot::tracker {

class ThesisSolver final : public PoseSolver {
 public:
  ThesisSolver(const Camera& cam, const LedModel& model, bool median_filter = true);

  [[nodiscard]] std::string_view name() const override { return "thesis"; }
  std::optional<Pose> solve(const SolveRequest& req) override;
  void reset() override;
  [[nodiscard]] int latency_frames() const override { return median_ ? 2 : 0; }

  /// Gauss-Newton on eq. 48 from `r0`; returns the distances (mm).
  [[nodiscard]] std::array<double, 4> solve_distances(const std::array<Vec3, 4>& bearings,
                                                      const std::array<double, 4>& r0) const;

 private:
  Camera cam_;
  LedModel model_;
  bool median_;
  std::array<double, 4> r_prev_{};
  bool have_prev_ = false;
  std::deque<std::array<double, 4>> history_;  // last five solutions (bounded)
};

/// Absolute orientation (eq. 50-56): R, t minimising sum |P_i - (R Q_i + t)|^2
/// through the SVD of the cross-covariance, with the reflection case handled.
[[nodiscard]] Pose absolute_orientation(const std::array<Vec3, 4>& model_pts,
                                        const std::array<Vec3, 4>& measured_pts);

}  // namespace earshot::tracker
