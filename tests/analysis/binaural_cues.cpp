#include "binaural_cues.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "earshot/audio/real_fft.hpp"

namespace earshot::analysis {

double itd_s(std::span<const float> left, std::span<const float> right, double sample_rate, double max_lag_s,
             double max_hz) {
  if (left.size() != right.size() || left.empty()) throw std::invalid_argument("itd_s: ears differ in length");
  constexpr std::size_t kUp = 8;
  const std::size_t n = std::bit_ceil(2 * left.size());
  audio::RealFft fft(n), up(n * kUp);
  std::vector<float> buf(n, 0.0f);
  std::vector<std::complex<float>> L(fft.bins()), R(fft.bins()), X(up.bins());
  std::copy(left.begin(), left.end(), buf.begin());
  fft.forward(buf, L);
  std::fill(buf.begin(), buf.end(), 0.0f);
  std::copy(right.begin(), right.end(), buf.begin());
  fft.forward(buf, R);
  // xc(k) = sum_n l[n] r[n + k]: a peak at k > 0 means the right ear lags.
  // Zero-padding the cross-spectrum interpolates xc at 1/kUp sample steps.
  std::fill(X.begin(), X.end(), std::complex<float>{});
  for (std::size_t b = 0; b < fft.bins(); ++b)
    if (max_hz <= 0.0 || double(b) * sample_rate / double(n) <= max_hz) X[b] = std::conj(L[b]) * R[b];
  X[fft.bins() - 1] *= 0.5f;  // the Nyquist bin is shared by both halves
  std::vector<float> xc(up.size());
  up.inverse(X, xc);
  const auto max_k = static_cast<long>(std::ceil(max_lag_s * sample_rate * kUp));
  const auto N = static_cast<long>(xc.size());
  auto at = [&](long k) { return double(xc[static_cast<std::size_t>((k % N + N) % N)]); };
  long best = 0;
  for (long k = -max_k; k <= max_k; ++k)
    if (at(k) > at(best)) best = k;
  const double a = at(best - 1), b = at(best), c = at(best + 1), den = a - 2 * b + c;
  const double frac = den < 0 ? 0.5 * (a - c) / den : 0.0;
  return (static_cast<double>(best) + frac) / static_cast<double>(kUp) / sample_rate;
}

double ild_db(std::span<const float> left, std::span<const float> right) {
  double el = 0, er = 0;
  for (float v : left) el += double(v) * v;
  for (float v : right) er += double(v) * v;
  return 10.0 * std::log10(el / er);
}

double energy_above_db(std::span<const float> x, double sample_rate, double cutoff_hz, std::size_t frame) {
  if (x.size() < frame) throw std::invalid_argument("energy_above_db: signal shorter than one frame");
  audio::RealFft fft(frame);
  std::vector<float> w(frame), buf(frame);
  for (std::size_t i = 0; i < frame; ++i)
    w[i] = static_cast<float>(0.5 - 0.5 * std::cos(2 * std::numbers::pi * double(i) / double(frame)));
  std::vector<std::complex<float>> S(fft.bins());
  std::vector<double> power(fft.bins(), 0.0);
  for (std::size_t at = 0; at + frame <= x.size(); at += frame / 2) {
    for (std::size_t i = 0; i < frame; ++i) buf[i] = x[at + i] * w[i];
    fft.forward(buf, S);
    for (std::size_t b = 0; b < S.size(); ++b) power[b] += std::norm(S[b]);
  }
  double total = 0, above = 0;
  for (std::size_t b = 1; b < power.size(); ++b) {  // the DC bin carries no pitch
    total += power[b];
    if (double(b) * sample_rate / double(frame) >= cutoff_hz) above += power[b];
  }
  return 10.0 * std::log10(std::max(above, 1e-300) / total);
}

}  // namespace earshot::analysis
