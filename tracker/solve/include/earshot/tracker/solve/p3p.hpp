// Minimal absolute pose from three points: Lambda Twist P3P
// (M. Persson, K. Nordberg, "Lambda Twist: An Accurate Fast Robust
// Perspective Three Point (P3P) Solver", ECCV 2018), written from the paper.
#pragma once

#include <array>

#include "earshot/tracker/core/geometry.hpp"

namespace earshot::tracker {

/// Up to four poses; `count` of `poses` are valid.
struct P3PSolutions {
  std::array<Pose, 4> poses;
  int count = 0;
};

/// Every real pose with bearing[i] ~ R * point[i] + t (unit bearings,
/// points in any unit; t comes out in the points' unit). Degenerate input
/// (collinear points, parallel bearings) gives no solution.
[[nodiscard]] P3PSolutions p3p_lambda_twist(const std::array<Vec3, 3>& bearings,
                                            const std::array<Vec3, 3>& points);

}  // namespace earshot::tracker
