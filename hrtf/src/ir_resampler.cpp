#include "earshot/hrtf/ir_resampler.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "dot.hpp"
#include "earshot/windowed_sinc.hpp"

namespace earshot::hrtf {
namespace {
constexpr double kPassband = 0.95;   // cut-off, as a fraction of the lower rate's Nyquist frequency
constexpr double kHalfLow = 32.0;    // kernel half-width in samples of the lower rate
constexpr double kBeta = 9.0;        // Kaiser shape: stopband near -90 dB
}  // namespace

std::size_t IrResampler::out_length_for(double from_hz, double to_hz, std::size_t in_length) {
  return static_cast<std::size_t>(std::ceil(static_cast<double>(in_length) * to_hz / from_hz - 1e-9));
}

IrResampler::IrResampler(double from_hz, double to_hz, std::size_t in_length) : in_length_(in_length) {
  if (!(from_hz > 0.0) || !(to_hz > 0.0)) throw std::invalid_argument("IrResampler: rates must be positive");
  const double step = from_hz / to_hz;                 // input samples per output sample
  const double s = kPassband * std::min(1.0, 1.0 / step);  // cut-off in cycles per half input sample
  const double half = kHalfLow * std::max(1.0, step);  // kernel half-width in input samples
  taps_ = 2 * static_cast<std::size_t>(std::ceil(half));
  const std::size_t out_length = out_length_for(from_hz, to_hz, in_length);
  first_.resize(out_length);
  weights_.assign(out_length * taps_, 0.0f);
  std::vector<double> w(taps_);
  const KaiserSinc kernel(s * half, kBeta);
  // With integer rates the output's place between input samples repeats
  // every `period` outputs (to / gcd of them), `advance` (from / gcd) input
  // samples later: 160 outputs for 44.1 -> 48 kHz. Each repeat takes the
  // first period's kernel (the window's Bessel functions are most of the
  // set's resampling time otherwise); other rates compute every kernel.
  std::size_t period = out_length, advance = 0;
  const bool whole = from_hz < 1e9 && to_hz < 1e9 && std::floor(from_hz) == from_hz && std::floor(to_hz) == to_hz;
  if (whole) {
    const auto from_i = static_cast<std::uint64_t>(from_hz), to_i = static_cast<std::uint64_t>(to_hz);
    const std::uint64_t g = std::gcd(from_i, to_i);
    period = static_cast<std::size_t>(to_i / g);
    advance = static_cast<std::size_t>(from_i / g);
  }
  for (std::size_t n = 0; n < out_length; ++n) {
    if (n >= period) {
      first_[n] = first_[n - period] + static_cast<std::int64_t>(advance);
      std::copy_n(weights_.begin() + static_cast<std::ptrdiff_t>((n - period) * taps_), taps_,
                  weights_.begin() + static_cast<std::ptrdiff_t>(n * taps_));
      continue;
    }
    const double t = static_cast<double>(n) * step;  // where output n sits on the input's time axis
    const auto k0 = static_cast<std::int64_t>(std::floor(t)) - static_cast<std::int64_t>(taps_ / 2) + 1;
    first_[n] = k0;
    double sum = 0.0;
    for (std::size_t j = 0; j < taps_; ++j) {
      const double x = t - static_cast<double>(k0 + static_cast<std::int64_t>(j));
      w[j] = std::abs(x) < half ? s * kernel(s * x) : 0.0;
      sum += w[j];
    }
    // Unit DC gain at every output position: no ripple at the output rate.
    for (std::size_t j = 0; j < taps_; ++j) weights_[n * taps_ + j] = static_cast<float>(w[j] / sum);
  }
}

void IrResampler::process(std::span<const float> in, std::span<float> out) const {
  if (in.size() != in_length_ || out.size() != first_.size())
    throw std::invalid_argument("IrResampler: wrong buffer lengths");
  const auto n_in = static_cast<std::int64_t>(in_length_);
  for (std::size_t n = 0; n < first_.size(); ++n) {
    const std::int64_t k0 = first_[n];
    const float* w = weights_.data() + n * taps_;
    // The taps that fall inside the response (zeros outside it).
    const std::int64_t lo = std::max<std::int64_t>(0, -k0);
    const std::int64_t hi = std::min<std::int64_t>(static_cast<std::int64_t>(taps_), n_in - k0);
    out[n] = hi > lo ? detail::dot(w + lo, in.data() + (k0 + lo), static_cast<std::size_t>(hi - lo)) : 0.0f;
  }
}

}  // namespace earshot::hrtf
