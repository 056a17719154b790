// Template definitions for filters.hpp.
#pragma once

#include <cmath>
#include <numbers>

namespace earshot::tracker {

template <int N>
double OneEuroFilter<N>::alpha(double cutoff, double dt) {
  const double tau = 1.0 / (2.0 * std::numbers::pi * cutoff);
  return 1.0 / (1.0 + tau / dt);
}

template <int N>
typename OneEuroFilter<N>::Vec OneEuroFilter<N>::filter(const Vec& x, double t) {
  if (!have_ || !(t > t_prev_)) {
    const bool first = !have_;
    have_ = true;
    if (first) {
      x_prev_ = x;
      dx_prev_.setZero();
    }
    t_prev_ = t;
    return x_prev_ = (first ? x : x_prev_);
  }
  const double dt = t - t_prev_;
  t_prev_ = t;
  const Vec dx = (x - x_prev_) / dt;
  const double ad = alpha(p_.derivative_cutoff_hz, dt);
  dx_prev_ = ad * dx + (1.0 - ad) * dx_prev_;
  const double cutoff = p_.min_cutoff_hz + p_.beta * dx_prev_.norm();
  const double a = alpha(cutoff, dt);
  x_prev_ = a * x + (1.0 - a) * x_prev_;
  return x_prev_;
}

}  // namespace earshot::tracker
