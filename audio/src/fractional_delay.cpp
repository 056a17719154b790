#include "earshot/audio/fractional_delay.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace earshot::audio {
namespace {

constexpr std::size_t kTaps = FractionalDelay::kTaps;
constexpr std::size_t kPhases = FractionalDelay::kPhases;
constexpr double kHalf = kTaps / 2;
constexpr double kBeta = 7.0;  // Kaiser window: sidelobes near -70 dB

double bessel_i0(double x) {
  double sum = 1.0, term = 1.0;
  for (int k = 1; k < 40; ++k) {
    term *= (x / (2.0 * k)) * (x / (2.0 * k));
    sum += term;
  }
  return sum;
}

/// Row p holds the taps for a fraction p / kPhases, ordered from the oldest
/// sample read to the newest, each row normalised to unit DC gain. Built once
/// and never written again: shared by every delay line.
const std::vector<float>& kernel_table() {
  static const std::vector<float> table = [] {
    std::vector<float> t((kPhases + 1) * kTaps);
    for (std::size_t p = 0; p <= kPhases; ++p) {
      const double frac = static_cast<double>(p) / kPhases;
      std::array<double, kTaps> row{};
      double sum = 0.0;
      for (std::size_t i = 0; i < kTaps; ++i) {
        // Tap i reads the sample (kHalf - i) older than the integer delay.
        const double x = kHalf - static_cast<double>(i) - frac;
        double sinc = 1.0;
        if (x != 0.0) sinc = (x == std::round(x)) ? 0.0 : std::sin(std::numbers::pi * x) / (std::numbers::pi * x);
        const double r = x / kHalf;
        const double w = std::abs(r) >= 1.0 ? 0.0 : bessel_i0(kBeta * std::sqrt(1.0 - r * r)) / bessel_i0(kBeta);
        row[i] = sinc * w;
        sum += row[i];
      }
      for (std::size_t i = 0; i < kTaps; ++i) t[p * kTaps + i] = static_cast<float>(row[i] / sum);
    }
    return t;
  }();
  return table;
}

}  // namespace

FractionalDelay::FractionalDelay(std::size_t block, double max_delay_samples)
    : max_delay_(std::max(kMinDelay, max_delay_samples)), kernels_(kernel_table().data()) {
  size_ = std::bit_ceil(block + static_cast<std::size_t>(std::ceil(max_delay_)) + kTaps + 2);
  ring_.assign(size_ + kTaps, 0.0f);
}

void FractionalDelay::reset() {
  std::fill(ring_.begin(), ring_.end(), 0.0f);
  delay_ = -1.0;
}

double FractionalDelay::clamp_delay(double delay_samples) const {
  return std::clamp(std::isfinite(delay_samples) ? delay_samples : kMinDelay, kMinDelay, max_delay_);
}

void FractionalDelay::process(std::span<const float> in, std::span<float> out, double delay_samples) {
  const double target = clamp_delay(delay_samples);
  write(in);
  read(out, delay_ < 0.0 ? target : delay_, target);
  delay_ = target;
}

void FractionalDelay::write(std::span<const float> in) {
  const std::size_t mask = size_ - 1;
  for (const float x : in) {
    ring_[write_] = x;
    if (write_ < kTaps) ring_[size_ + write_] = x;  // the mirror keeps every read contiguous
    write_ = (write_ + 1) & mask;
  }
}

void FractionalDelay::read(std::span<float> out, double from, double to) const {
  const double start = clamp_delay(from), target = clamp_delay(to);
  const std::size_t n = out.size(), mask = size_ - 1;
  const std::size_t block_start = (write_ + size_ - n) & mask;  // where out[0]'s input sample was written
  // Oldest sample the kernel reads: kHalf samples before the integer delay.
  auto first_read = [&](std::size_t i, std::size_t whole) {
    return (block_start + i + size_ - whole - static_cast<std::size_t>(kHalf)) & mask;
  };
  auto split = [](double d, std::size_t& whole, std::size_t& phase) {
    whole = static_cast<std::size_t>(d);
    phase = static_cast<std::size_t>((d - static_cast<double>(whole)) * kPhases + 0.5);
    if (phase == kPhases) phase = 0, ++whole;
  };
  std::size_t whole = 0, phase = 0;
  if (start == target) {
    // A still delay: one kernel for the whole block, and while the ring
    // does not wrap the samples are contiguous, so the loop runs across
    // output samples, which vectorises.
    split(target, whole, phase);
    const std::size_t first = first_read(0, whole);
    if (first + n + kTaps <= size_ + kTaps) {
      const float* x = ring_.data() + first;
      const float* k = kernels_ + phase * kTaps;
      std::fill(out.begin(), out.end(), 0.0f);
      for (std::size_t t = 0; t < kTaps; ++t) {
        const float kt = k[t];
        const float* xt = x + t;
        for (std::size_t i = 0; i < n; ++i) out[i] += kt * xt[i];
      }
      return;
    }
  }
  // A moving delay: the read position in 32.32 fixed point, so the whole
  // and fractional parts come from shifts rather than float conversions.
  constexpr double kOne = 4294967296.0;  // 2^32
  const auto pos0 = static_cast<std::int64_t>(start * kOne);
  const auto pos_step = static_cast<std::int64_t>((target - start) / static_cast<double>(n) * kOne);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t pos = pos0 + pos_step * static_cast<std::int64_t>(i + 1);
    whole = static_cast<std::size_t>(pos >> 32);
    phase = static_cast<std::size_t>(((pos & 0xFFFFFFFF) + (std::int64_t{1} << 21)) >> 22);  // rounded to 1/1024
    if (phase == kPhases) phase = 0, ++whole;
    const float* x = ring_.data() + first_read(i, whole);
    const float* k = kernels_ + phase * kTaps;
    // Lane-wise partial sums the compiler turns into SIMD, then a fixed
    // summation order: fast, and the same result on every run.
    std::array<float, kTaps / 2> lanes;
    for (std::size_t t = 0; t < kTaps / 2; ++t) lanes[t] = k[t] * x[t] + k[t + kTaps / 2] * x[t + kTaps / 2];
    for (std::size_t w = kTaps / 4; w > 0; w /= 2)
      for (std::size_t t = 0; t < w; ++t) lanes[t] += lanes[t + w];
    out[i] = lanes[0];
  }
}

}  // namespace earshot::audio
