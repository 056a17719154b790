#include "earshot/hrtf/rigid_sphere.hpp"

#include <algorithm>
#include <cmath>

namespace earshot::hrtf {
namespace {

using cd = std::complex<double>;
constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxTerms = 2000;
constexpr double kThreshold = 1e-12;

}  // namespace

RigidSphereSeries::RigidSphereSeries(double r, double f, const SphereHead& head) {
  const double a = head.radius_m;
  const double rho = r / a;
  const double mu = 2.0 * kPi * f * a / head.speed_of_sound;
  const bool plane = std::isinf(rho);
  double largest = 0.0;
  int small = 0;
  // True once two coefficients in a row are negligible past m = mu + 2.
  const auto done = [&](int m, const cd& c) {
    largest = std::max(largest, std::abs(c));
    small = std::abs(c) <= kThreshold * largest ? small + 1 : 0;
    return small >= 2 && m > mu + 2.0;
  };
  if (mu == 0.0) {
    // The quasi-static limit: (2m + 1) / (m + 1) rho^-m (only m = 0 for a plane wave).
    double scale = 1.0;
    for (int m = 0; m < kMaxTerms; ++m) {
      c_.emplace_back((2.0 * m + 1.0) / (m + 1.0) * scale, 0.0);
      if (plane || done(m, c_.back())) break;
      scale /= rho;
    }
    return;
  }
  const double xr = mu * rho;
  const cd i(0.0, 1.0);
  const cd e_s = std::exp(i * mu);
  cd hs_prev = -i * e_s / mu, hs = -e_s * (mu + i) / (mu * mu);  // h_0(mu), h_1(mu)
  cd hr_prev, hr;                                                  // h_0, h_1 at mu rho
  if (!plane) {
    const cd e_r = std::exp(i * xr);
    hr_prev = -i * e_r / xr;
    hr = -e_r * (xr + i) / (xr * xr);
  }
  // Prefactors: -(rho / mu) e^{-i mu rho} for a point source; for a plane
  // wave h_m(mu rho) tends to (-i)^{m+1} e^{i mu rho} / (mu rho), which leaves
  // i (-i)^m / mu^2.
  const cd pre = plane ? 1.0 / (mu * mu) : -(rho / mu) * std::exp(-i * xr);
  cd minus_i_pow = 1.0;  // (-i)^m
  for (int m = 0; m < kMaxTerms; ++m) {
    // h'_m(mu) (h'_0 = -h_1, else h_{m-1} - (m + 1) / mu h_m) and h_m(mu rho).
    const cd dh = m == 0 ? -hs : hs_prev - (m + 1.0) / mu * hs;
    const cd hm_r = m == 0 ? hr_prev : hr;
    const cd c = pre * (2.0 * m + 1.0) * (plane ? i * minus_i_pow : hm_r) / dh;
    if (!std::isfinite(c.real()) || !std::isfinite(c.imag())) break;
    c_.push_back(c);
    if (done(m, c)) break;
    if (m > 0) {  // advance the Hankel functions to m + 1 (m = 0 starts with h_0, h_1 in place)
      const cd s_next = (2.0 * m + 1.0) / mu * hs - hs_prev;
      hs_prev = hs;
      hs = s_next;
      if (!plane) {
        const cd r_next = (2.0 * m + 1.0) / xr * hr - hr_prev;
        hr_prev = hr;
        hr = r_next;
      }
    }
    minus_i_pow *= -i;
  }
}

std::complex<double> RigidSphereSeries::at(double theta) const {
  const double x = std::cos(theta);
  double p_prev = 0.0, p = 1.0;  // P_{m-1}, P_m
  cd sum = 0.0;
  for (std::size_t m = 0; m < c_.size(); ++m) {
    sum += c_[m] * p;
    const double md = static_cast<double>(m);
    const double next = ((2.0 * md + 1.0) * x * p - md * p_prev) / (md + 1.0);
    p_prev = p;
    p = next;
  }
  return sum;
}

std::complex<double> rigid_sphere_response(double r, double theta, double f, const SphereHead& head) {
  return RigidSphereSeries(r, f, head).at(theta);
}

double sphere_path_delay(double r, double theta, const SphereHead& head) {
  const double a = head.radius_m, c = head.speed_of_sound;
  theta = std::clamp(std::abs(theta), 0.0, kPi);
  if (std::isinf(r)) {
    // Plane wave: -a cos(theta) while the point is lit, a (theta - pi/2) around.
    return (theta <= 0.5 * kPi ? -a * std::cos(theta) : a * (theta - 0.5 * kPi)) / c;
  }
  const double tangent = std::acos(std::clamp(a / r, -1.0, 1.0));
  if (theta <= tangent) return (std::sqrt(r * r + a * a - 2.0 * a * r * std::cos(theta)) - r) / c;
  return (std::sqrt(r * r - a * a) + a * (theta - tangent) - r) / c;
}

}  // namespace earshot::hrtf
