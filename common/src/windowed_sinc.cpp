#include "earshot/windowed_sinc.hpp"

#include <cmath>
#include <numbers>

namespace earshot {

double bessel_i0(double x) {
  double sum = 1.0, term = 1.0;
  for (int k = 1; k < 40; ++k) {
    term *= (x / (2.0 * k)) * (x / (2.0 * k));
    sum += term;
    if (term < 1e-17 * sum) break;  // the rest cannot change the double
  }
  return sum;
}

KaiserSinc::KaiserSinc(double half_width, double beta)
    : half_width_(half_width), beta_(beta), i0_beta_(bessel_i0(beta)) {}

double KaiserSinc::operator()(double x) const {
  double sinc = 1.0;
  if (x != 0.0) sinc = (x == std::round(x)) ? 0.0 : std::sin(std::numbers::pi * x) / (std::numbers::pi * x);
  const double r = x / half_width_;
  const double w = std::abs(r) >= 1.0 ? 0.0 : bessel_i0(beta_ * std::sqrt(1.0 - r * r)) / i0_beta_;
  return sinc * w;
}

double kaiser_sinc(double x, double half_width, double beta) { return KaiserSinc(half_width, beta)(x); }

}  // namespace earshot
