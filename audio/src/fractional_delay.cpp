#include "earshot/audio/fractional_delay.hpp"

#include "earshot/windowed_sinc.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "simd/glide.hpp"

namespace earshot::audio {
namespace {

constexpr std::size_t kTaps = FractionalDelay::kTaps;
constexpr std::size_t kCells = FractionalDelay::kCells;
constexpr double kHalf = kTaps / 2;
constexpr double kBeta = 7.0;  // Kaiser window: sidelobes near -70 dB
constexpr std::size_t kCellStride = simd::kCellStride;  // a0, a1, a2 of one cell, as the glide kernels read it
// Sixteen reads in one cell reach kTaps + 15 samples past the first: the ring
// repeats its first kMirror samples past its end so no read wraps.
constexpr std::size_t kMirror = kTaps + 16;

/// The exact kernel for a fraction in [0, 1]: a Kaiser-windowed sinc, taps
/// ordered from the oldest sample read to the newest, unit DC gain.
std::array<double, kTaps> exact_kernel(double frac) {
  std::array<double, kTaps> row{};
  double sum = 0.0;
  for (std::size_t i = 0; i < kTaps; ++i) {
    // Tap i reads the sample (kHalf - i) older than the integer delay.
    row[i] = kaiser_sinc(kHalf - static_cast<double>(i) - frac, kHalf, kBeta);
    sum += row[i];
  }
  for (double& v : row) v /= sum;
  return row;
}

/// Cell c covers fractions [c, c + 1) / kCells; within it the kernel is the
/// quadratic a0 + a1 u + a2 u^2 (u = 0..1 across the cell) through the exact
/// kernels at the cell's start, middle and end. So it is continuous from
/// cell to cell, exact at whole delays, and within 106 dB of the exact
/// kernel's response up to 20 kHz (the linear interpolation between 128
/// rows it replaced: 85 dB). Built once, never written again: shared by
/// every delay line.
const std::vector<float>& kernel_table() {
  static const std::vector<float> table = [] {
    std::vector<float> t(kCells * kCellStride);
    for (std::size_t c = 0; c < kCells; ++c) {
      const auto k0 = exact_kernel(static_cast<double>(c) / kCells);
      const auto kh = exact_kernel((static_cast<double>(c) + 0.5) / kCells);
      const auto k1 = exact_kernel(static_cast<double>(c + 1) / kCells);
      float* a = t.data() + c * kCellStride;
      for (std::size_t i = 0; i < kTaps; ++i) {
        a[i] = static_cast<float>(k0[i]);
        a[kTaps + i] = static_cast<float>(-3.0 * k0[i] + 4.0 * kh[i] - k1[i]);
        a[2 * kTaps + i] = static_cast<float>(2.0 * k0[i] - 4.0 * kh[i] + 2.0 * k1[i]);
      }
    }
    return t;
  }();
  return table;
}

}  // namespace

FractionalDelay::FractionalDelay(std::size_t block, double max_delay_samples, const simd::Kernels& isa_kernels)
    : max_delay_(std::max(kMinDelay, max_delay_samples)), kernels_(kernel_table().data()), simd_(&isa_kernels) {
  size_ = std::bit_ceil(block + static_cast<std::size_t>(std::ceil(max_delay_)) + kMirror + 2);
  ring_.assign(size_ + kMirror, 0.0f);
}

void FractionalDelay::reset() {
  std::fill(ring_.begin(), ring_.end(), 0.0f);
  delay_ = -1.0;
}

void FractionalDelay::process(std::span<const float> in, std::span<float> out, double delay_samples) {
  const double target = clamp_delay(delay_samples);
  write(in);
  read(out, delay_ < 0.0 ? target : delay_, target);
  delay_ = target;
}

void FractionalDelay::write(std::span<const float> in) {
  // In at most two runs (the ring wraps once at most per block), then the
  // mirror of the ring's first kMirror samples past its end.
  std::size_t done = 0;
  while (done < in.size()) {
    const std::size_t run = std::min(in.size() - done, size_ - write_);
    std::copy_n(in.begin() + static_cast<std::ptrdiff_t>(done), run, ring_.begin() + static_cast<std::ptrdiff_t>(write_));
    if (write_ < kMirror) {
      const std::size_t m = std::min(run, kMirror - write_);
      std::copy_n(ring_.begin() + static_cast<std::ptrdiff_t>(write_), m, ring_.begin() + static_cast<std::ptrdiff_t>(size_ + write_));
    }
    done += run;
    write_ = (write_ + run) & (size_ - 1);
  }
}

void FractionalDelay::prefetch(std::size_t n, double shortest, double longest) const {
  const double lo = clamp_delay(std::min(shortest, longest)), hi = clamp_delay(std::max(shortest, longest));
  // The next block's sample i goes to write_ + i; its kernels read from
  // kHalf samples before the longest whole delay to kHalf after the
  // shortest, with two samples' margin for motion either side.
  const std::size_t reach = static_cast<std::size_t>(hi) + static_cast<std::size_t>(kHalf) + 2;
  const std::size_t from = (write_ + size_ - reach) & (size_ - 1);
  const std::size_t span = n + static_cast<std::size_t>(hi - lo) + kTaps + 4;
  for (std::size_t i = 0; i < span + 15; i += 16) __builtin_prefetch(ring_.data() + ((from + i) & (size_ - 1)), 0, 3);
  // And where write() will put the block: written size_ samples ago.
  for (std::size_t i = 0; i < n + 15; i += 16) __builtin_prefetch(ring_.data() + ((write_ + i) & (size_ - 1)), 1, 3);
}

void FractionalDelay::read(std::span<float> out, double from, double to) const {
  const double start = clamp_delay(from), target = clamp_delay(to);
  const std::size_t n = out.size(), mask = size_ - 1;
  const std::size_t block_start = (write_ + size_ - n) & mask;  // where out[0]'s input sample was written
  if (start == target) {
    // A still delay: one kernel for the whole block, and while the ring
    // does not wrap the samples are contiguous, so the loop runs across
    // output samples, which vectorises.
    const auto whole = static_cast<std::size_t>(target);
    const double scaled = (target - static_cast<double>(whole)) * kCells;
    const std::size_t cell = std::min(static_cast<std::size_t>(scaled), kCells - 1);
    const auto u = static_cast<float>(scaled - static_cast<double>(cell));
    // Oldest sample the kernel reads: kHalf samples before the integer delay.
    const std::size_t first = (block_start + size_ - whole - static_cast<std::size_t>(kHalf)) & mask;
    if (first + n + kTaps <= size_ + kMirror) {
      const float* x = ring_.data() + first;
      const float* a = kernels_ + cell * kCellStride;
      std::array<float, kTaps> k;
      for (std::size_t t = 0; t < kTaps; ++t) k[t] = a[t] + u * (a[kTaps + t] + u * a[2 * kTaps + t]);
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
  // samples, cell and place in the cell come from shifts and masks.
  constexpr double kOne = 4294967296.0;  // 2^32
  const auto pos0 = static_cast<std::int64_t>(start * kOne);
  const auto pos_step = static_cast<std::int64_t>((target - start) / static_cast<double>(n) * kOne);
  const simd::Glide g{ring_.data(), mask, block_start + size_ - static_cast<std::size_t>(kHalf), pos0, pos_step, kernels_};
  simd_->glide(g, out.data(), n);
}

}  // namespace earshot::audio
