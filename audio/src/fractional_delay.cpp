#include "earshot/audio/fractional_delay.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define EARSHOT_DELAY_AVX2 1
#endif

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

/// Entry p holds the taps for a fraction p / kPhases, ordered from the
/// oldest sample read to the newest, each row normalised to unit DC gain,
/// then their change to entry p + 1: a fraction between gets the row
/// interpolated linearly, k = row + f * delta (kStride floats per entry).
/// Built once and never written again: shared by every delay line.
constexpr std::size_t kStride = 2 * kTaps;
const std::vector<float>& kernel_table() {
  static const std::vector<float> table = [] {
    std::vector<std::array<double, kTaps>> rows(kPhases + 1);
    for (std::size_t p = 0; p <= kPhases; ++p) {
      const double frac = static_cast<double>(p) / kPhases;
      std::array<double, kTaps>& row = rows[p];
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
      for (double& v : row) v /= sum;
    }
    std::vector<float> t(kPhases * kStride);
    for (std::size_t p = 0; p < kPhases; ++p)
      for (std::size_t i = 0; i < kTaps; ++i) {
        t[p * kStride + i] = static_cast<float>(rows[p][i]);
        t[p * kStride + kTaps + i] = static_cast<float>(rows[p + 1][i] - rows[p][i]);
      }
    return t;
  }();
  return table;
}

/// A gliding read's walk: sample i reads at pos = pos0 + step (i + 1)
/// (32.32 fixed point, in samples of delay), so its kernel starts at ring
/// index (base + i - whole(pos)) & mask, and its taps are table entry
/// phase(pos) interpolated by the rest of the fraction.
struct Glide {
  const float* ring;
  std::size_t mask, base;
  std::int64_t pos0, step;
  const float* table;
};
constexpr int kPhaseBits = std::countr_zero(kPhases);
constexpr int kRestBits = 32 - kPhaseBits;
constexpr float kRestScale = 1.0f / static_cast<float>(std::uint32_t{1} << kRestBits);

/// One sample of the walk, the reference way: eight lane sums, then halved pairwise.
float glide_sample(const Glide& g, std::size_t i) {
  const std::int64_t pos = g.pos0 + g.step * static_cast<std::int64_t>(i + 1);
  const auto fraction = static_cast<std::uint32_t>(pos & 0xFFFFFFFF);
  const float* x = g.ring + ((g.base + i - static_cast<std::size_t>(pos >> 32)) & g.mask);
  const float* row = g.table + (fraction >> kRestBits) * kStride;
  const float* delta = row + kTaps;
  const float f = static_cast<float>(fraction & ((std::uint32_t{1} << kRestBits) - 1)) * kRestScale;
  std::array<float, kTaps / 2> lanes;
  for (std::size_t t = 0; t < kTaps / 2; ++t) {
    const std::size_t u = t + kTaps / 2;
    lanes[t] = (row[t] + f * delta[t]) * x[t] + (row[u] + f * delta[u]) * x[u];
  }
  for (std::size_t w = kTaps / 4; w > 0; w /= 2)
    for (std::size_t t = 0; t < w; ++t) lanes[t] += lanes[t + w];
  return lanes[0];
}

void glide_generic(const Glide& g, float* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = glide_sample(g, i);
}

#ifdef EARSHOT_DELAY_AVX2
/// The same with AVX2, eight samples at a time: one 8-lane product per
/// sample, then the eight vectors transposed and summed together (three
/// rounds of horizontal adds) rather than one horizontal sum per sample.
/// A last group of fewer than eight takes the reference way.
__attribute__((target("avx2,fma"))) void glide_avx2(const Glide& g, float* out, std::size_t n) {
  // The fractions' low 32 bits need only 32-bit arithmetic: eight at once.
  const auto p0 = static_cast<std::uint32_t>(g.pos0), st = static_cast<std::uint32_t>(g.step);
  const __m256i steps = _mm256_mullo_epi32(_mm256_set1_epi32(static_cast<int>(st)), _mm256_setr_epi32(1, 2, 3, 4, 5, 6, 7, 8));
  const __m256i rest_mask = _mm256_set1_epi32((1 << kRestBits) - 1);
  alignas(32) std::uint32_t phase[8];
  alignas(32) float f[8];
  std::size_t i0 = 0;
  for (; i0 + 8 <= n; i0 += 8) {
    const __m256i frac = _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(p0 + st * static_cast<std::uint32_t>(i0))), steps);
    _mm256_store_si256(reinterpret_cast<__m256i*>(phase), _mm256_srli_epi32(frac, kRestBits));
    _mm256_store_ps(f, _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(frac, rest_mask)), _mm256_set1_ps(kRestScale)));
    __m256 s[8];
    for (std::size_t j = 0; j < 8; ++j) {
      const std::size_t i = i0 + j;
      const auto whole = static_cast<std::size_t>((g.pos0 + g.step * static_cast<std::int64_t>(i + 1)) >> 32);
      const float* x = g.ring + ((g.base + i - whole) & g.mask);
      const float* k = g.table + phase[j] * kStride;
      const __m256 fj = _mm256_broadcast_ss(f + j);
      const __m256 lo = _mm256_fmadd_ps(fj, _mm256_loadu_ps(k + 16), _mm256_loadu_ps(k));
      const __m256 hi = _mm256_fmadd_ps(fj, _mm256_loadu_ps(k + 24), _mm256_loadu_ps(k + 8));
      s[j] = _mm256_fmadd_ps(hi, _mm256_loadu_ps(x + 8), _mm256_mul_ps(lo, _mm256_loadu_ps(x)));
    }
    const __m256 t0 = _mm256_hadd_ps(s[0], s[1]), t1 = _mm256_hadd_ps(s[2], s[3]);
    const __m256 t2 = _mm256_hadd_ps(s[4], s[5]), t3 = _mm256_hadd_ps(s[6], s[7]);
    const __m256 u0 = _mm256_hadd_ps(t0, t1), u1 = _mm256_hadd_ps(t2, t3);  // halves of samples 0-3, 4-7
    _mm256_storeu_ps(out + i0,
                     _mm256_add_ps(_mm256_permute2f128_ps(u0, u1, 0x20), _mm256_permute2f128_ps(u0, u1, 0x31)));
  }
  for (; i0 < n; ++i0) out[i0] = glide_sample(g, i0);
}
#endif

}  // namespace

FractionalDelay::FractionalDelay(std::size_t block, double max_delay_samples)
    : max_delay_(std::max(kMinDelay, max_delay_samples)), kernels_(kernel_table().data()) {
  size_ = std::bit_ceil(block + static_cast<std::size_t>(std::ceil(max_delay_)) + kTaps + 2);
  ring_.assign(size_ + kTaps, 0.0f);
#ifdef EARSHOT_DELAY_AVX2
  avx2_ = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
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
  // In at most two runs (the ring wraps once at most per block), then the
  // mirror of the ring's first kTaps samples past its end.
  std::size_t done = 0;
  while (done < in.size()) {
    const std::size_t run = std::min(in.size() - done, size_ - write_);
    std::copy_n(in.begin() + static_cast<std::ptrdiff_t>(done), run, ring_.begin() + static_cast<std::ptrdiff_t>(write_));
    if (write_ < kTaps) {
      const std::size_t m = std::min(run, kTaps - write_);
      std::copy_n(ring_.begin() + static_cast<std::ptrdiff_t>(write_), m, ring_.begin() + static_cast<std::ptrdiff_t>(size_ + write_));
    }
    done += run;
    write_ = (write_ + run) & (size_ - 1);
  }
  // The next block's samples go where the ring was last written size_
  // samples ago, long out of cache: ask for those lines now, so the next
  // write does not wait on memory.
  for (std::size_t i = 0; i < in.size(); i += 16) __builtin_prefetch(ring_.data() + ((write_ + i) & (size_ - 1)), 1, 1);
}

void FractionalDelay::read(std::span<float> out, double from, double to) const {
  const double start = clamp_delay(from), target = clamp_delay(to);
  const std::size_t n = out.size(), mask = size_ - 1;
  const std::size_t block_start = (write_ + size_ - n) & mask;  // where out[0]'s input sample was written
  // Oldest sample the kernel reads: kHalf samples before the integer delay.
  auto first_read = [&](std::size_t i, std::size_t whole) {
    return (block_start + i + size_ - whole - static_cast<std::size_t>(kHalf)) & mask;
  };
  // A delay's whole samples, table entry and fraction within the entry.
  auto split = [](double d, std::size_t& whole, std::size_t& phase, float& f) {
    whole = static_cast<std::size_t>(d);
    const double scaled = (d - static_cast<double>(whole)) * kPhases;
    phase = std::min(static_cast<std::size_t>(scaled), kPhases - 1);
    f = static_cast<float>(scaled - static_cast<double>(phase));
  };
  std::size_t whole = 0, phase = 0;
  float f = 0.0f;
  if (start == target) {
    // A still delay: one kernel for the whole block, and while the ring
    // does not wrap the samples are contiguous, so the loop runs across
    // output samples, which vectorises.
    split(target, whole, phase, f);
    const std::size_t first = first_read(0, whole);
    if (first + n + kTaps <= size_ + kTaps) {
      const float* x = ring_.data() + first;
      std::array<float, kTaps> k;
      for (std::size_t t = 0; t < kTaps; ++t) k[t] = kernels_[phase * kStride + t] + f * kernels_[phase * kStride + kTaps + t];
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
  const Glide g{ring_.data(), mask, block_start + size_ - static_cast<std::size_t>(kHalf), pos0, pos_step, kernels_};
#ifdef EARSHOT_DELAY_AVX2
  if (avx2_) return glide_avx2(g, out.data(), n);
#endif
  glide_generic(g, out.data(), n);
}

}  // namespace earshot::audio
