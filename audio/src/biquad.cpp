#include "earshot/audio/biquad.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace earshot::audio {
namespace {

// Analog section (n2 s^2 + n1 s + n0) / (d2 s^2 + d1 s + d0), s normalised so
// that s = j at fc, to digital through the bilinear transform pre-warped at fc.
BiquadCoeffs bilinear(double n2, double n1, double n0, double d2, double d1, double d0, double fc, double fs) {
  const double k = 1.0 / std::tan(std::numbers::pi * fc / fs);
  const double k2 = k * k;
  const double a0 = d2 * k2 + d1 * k + d0;
  BiquadCoeffs c;
  c.b0 = (n2 * k2 + n1 * k + n0) / a0;
  c.b1 = 2.0 * (n0 - n2 * k2) / a0;
  c.b2 = (n2 * k2 - n1 * k + n0) / a0;
  c.a1 = 2.0 * (d0 - d2 * k2) / a0;
  c.a2 = (d2 * k2 - d1 * k + d0) / a0;
  return c;
}

// Damping 2 cos(theta) of the Butterworth pole pairs of order 2N.
template <std::size_t N>
double pole_damping(std::size_t i) {
  const double theta = std::numbers::pi * (2.0 * double(i) + 1.0) / (4.0 * double(N));
  return 2.0 * std::sin(theta);
}

}  // namespace

template <std::size_t N>
std::array<BiquadCoeffs, N> butterworth_lowpass(double fc, double fs) {
  std::array<BiquadCoeffs, N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = bilinear(0, 0, 1, 1, pole_damping<N>(i), 1, fc, fs);
  return out;
}

template <std::size_t N>
std::array<BiquadCoeffs, N> butterworth_highpass(double fc, double fs) {
  std::array<BiquadCoeffs, N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = bilinear(1, 0, 0, 1, pole_damping<N>(i), 1, fc, fs);
  return out;
}

template std::array<BiquadCoeffs, 1> butterworth_lowpass<1>(double, double);
template std::array<BiquadCoeffs, 2> butterworth_lowpass<2>(double, double);
template std::array<BiquadCoeffs, 3> butterworth_lowpass<3>(double, double);
template std::array<BiquadCoeffs, 4> butterworth_lowpass<4>(double, double);
template std::array<BiquadCoeffs, 1> butterworth_highpass<1>(double, double);
template std::array<BiquadCoeffs, 2> butterworth_highpass<2>(double, double);
template std::array<BiquadCoeffs, 3> butterworth_highpass<3>(double, double);
template std::array<BiquadCoeffs, 4> butterworth_highpass<4>(double, double);

std::array<BiquadCoeffs, 2> high_shelf4(double fc, double f, double gain_at_f, double fs) {
  const double w = std::tan(std::numbers::pi * f / fs) / std::tan(std::numbers::pi * fc / fs);
  const double w8 = std::pow(w, 8.0);
  const double t2 = gain_at_f * gain_at_f;
  // Solve (1 + g^2 w^8) / (1 + w^8) = t^2 for the shelf's far gain g.
  const double g2 = std::max((t2 * (1.0 + w8) - 1.0) / w8, 1e-12);
  const double g = std::sqrt(g2);
  const double r = std::sqrt(g), q = std::sqrt(r);  // g^(1/2), g^(1/4)
  std::array<BiquadCoeffs, 2> out;
  for (std::size_t i = 0; i < 2; ++i) {
    const double d = pole_damping<2>(i);
    // Zeros are the Butterworth poles scaled by g^(-1/4): N(s) = B(g^(1/4) s).
    out[i] = bilinear(r, d * q, 1, 1, d, 1, fc, fs);
  }
  return out;
}

double magnitude(std::span<const BiquadCoeffs> cascade, double f, double fs) {
  const std::complex<double> z1 = std::polar(1.0, -2.0 * std::numbers::pi * f / fs);
  const std::complex<double> z2 = z1 * z1;
  double m = 1.0;
  for (const auto& c : cascade) m *= std::abs((c.b0 + c.b1 * z1 + c.b2 * z2) / (1.0 + c.a1 * z1 + c.a2 * z2));
  return m;
}

double group_delay(std::span<const BiquadCoeffs> cascade, double f, double fs) {
  // -d(phase)/d(omega) by a central difference; the phase is unwrapped per
  // section, which is smooth over a step this small.
  const double w = 2.0 * std::numbers::pi * f / fs, h = 1e-4;
  double tau = 0.0;
  for (const auto& c : cascade) {
    auto phase = [&](double x) {
      const std::complex<double> z1 = std::polar(1.0, -x), z2 = z1 * z1;
      return std::arg((c.b0 + c.b1 * z1 + c.b2 * z2) / (1.0 + c.a1 * z1 + c.a2 * z2));
    };
    double d = phase(w + h) - phase(w - h);
    if (d > std::numbers::pi) d -= 2.0 * std::numbers::pi;
    if (d < -std::numbers::pi) d += 2.0 * std::numbers::pi;
    tau -= d / (2.0 * h);
  }
  return tau;
}

}  // namespace earshot::audio
