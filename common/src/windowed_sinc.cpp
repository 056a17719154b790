#include "earshot/windowed_sinc.hpp"

#include <cmath>
#include <numbers>

namespace earshot {

double bessel_i0(double x) {
  double sum = 1.0, term = 1.0;
  for (int k = 1; k < 40; ++k) {
    term *= (x / (2.0 * k)) * (x / (2.0 * k));
    sum += term;
  }
  return sum;
}

double kaiser_sinc(double x, double half_width, double beta) {
  double sinc = 1.0;
  if (x != 0.0) sinc = (x == std::round(x)) ? 0.0 : std::sin(std::numbers::pi * x) / (std::numbers::pi * x);
  const double r = x / half_width;
  const double w = std::abs(r) >= 1.0 ? 0.0 : bessel_i0(beta * std::sqrt(1.0 - r * r)) / bessel_i0(beta);
  return sinc * w;
}

}  // namespace earshot
