#include "earshot/audio/fractional_delay.hpp"

#include "earshot/windowed_sinc.hpp"

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
constexpr std::size_t kCells = FractionalDelay::kCells;
constexpr double kHalf = kTaps / 2;
constexpr double kBeta = 7.0;  // Kaiser window: sidelobes near -70 dB
constexpr std::size_t kCellStride = 3 * kTaps;  // a0, a1, a2 of one cell
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

/// A gliding read's walk: sample i reads at pos = pos0 + step (i + 1), in
/// 32.32 fixed point samples of delay. Its top bits past the whole samples
/// name the cell (pos >> kUBits counts cells from delay 0), the rest is u.
/// Sample i's kernel starts at ring index (base + i - whole) & mask.
struct Glide {
  const float* ring;
  std::size_t mask, base;
  std::int64_t pos0, step;
  const float* table;
};
constexpr int kCellBits = std::countr_zero(kCells);
constexpr int kUBits = 32 - kCellBits;
constexpr std::int64_t kUMask = (std::int64_t{1} << kUBits) - 1;
constexpr float kUScale = 1.0f / static_cast<float>(std::int64_t{1} << kUBits);

std::int64_t walk(const Glide& g, std::size_t i) { return g.pos0 + g.step * static_cast<std::int64_t>(i + 1); }
/// Where the kernel of sample i starts when its cell (counted from delay 0) is `cell`.
const float* window(const Glide& g, std::size_t i, std::int64_t cell) {
  return g.ring + ((g.base + i - static_cast<std::size_t>(cell >> kCellBits)) & g.mask);
}
const float* coefficients(const Glide& g, std::int64_t cell) {
  return g.table + static_cast<std::size_t>(cell & (kCells - 1)) * kCellStride;
}

/// One sample of the walk, the reference way: eight lane sums, then halved pairwise.
float glide_sample(const Glide& g, std::size_t i) {
  const std::int64_t pos = walk(g, i), cell = pos >> kUBits;
  const float* x = window(g, i, cell);
  const float* a = coefficients(g, cell);
  const float u = static_cast<float>(pos & kUMask) * kUScale;
  std::array<float, kTaps / 2> lanes;
  for (std::size_t t = 0; t < kTaps / 2; ++t) {
    const std::size_t v = t + kTaps / 2;
    const float kt = a[t] + u * (a[kTaps + t] + u * a[2 * kTaps + t]);
    const float kv = a[v] + u * (a[kTaps + v] + u * a[2 * kTaps + v]);
    lanes[t] = kt * x[t] + kv * x[v];
  }
  for (std::size_t w = kTaps / 4; w > 0; w /= 2)
    for (std::size_t t = 0; t < w; ++t) lanes[t] += lanes[t + w];
  return lanes[0];
}

void glide_generic(const Glide& g, float* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = glide_sample(g, i);
}

#ifdef EARSHOT_DELAY_AVX2
/// Eight consecutive samples whose kernels all lie in one cell with one
/// whole delay: the three polynomial coefficients' FIRs, run across the
/// eight samples at once (lane j reads x[j + t]), then a0 + u (a1 + u a2)
/// per lane. Even and odd taps sum apart to halve the dependency chains.
__attribute__((target("avx2,fma"))) inline __m256 cell_fir(const float* x, const float* a, __m256 u) {
  __m256 e0 = _mm256_setzero_ps(), e1 = e0, e2 = e0, o0 = e0, o1 = e0, o2 = e0;
  for (std::size_t t = 0; t < kTaps; t += 2) {
    const __m256 xe = _mm256_loadu_ps(x + t), xo = _mm256_loadu_ps(x + t + 1);
    e0 = _mm256_fmadd_ps(_mm256_broadcast_ss(a + t), xe, e0);
    e1 = _mm256_fmadd_ps(_mm256_broadcast_ss(a + kTaps + t), xe, e1);
    e2 = _mm256_fmadd_ps(_mm256_broadcast_ss(a + 2 * kTaps + t), xe, e2);
    o0 = _mm256_fmadd_ps(_mm256_broadcast_ss(a + t + 1), xo, o0);
    o1 = _mm256_fmadd_ps(_mm256_broadcast_ss(a + kTaps + t + 1), xo, o1);
    o2 = _mm256_fmadd_ps(_mm256_broadcast_ss(a + 2 * kTaps + t + 1), xo, o2);
  }
  const __m256 z0 = _mm256_add_ps(e0, o0), z1 = _mm256_add_ps(e1, o1), z2 = _mm256_add_ps(e2, o2);
  return _mm256_fmadd_ps(u, _mm256_fmadd_ps(u, z2, z1), z0);
}

/// The same for sixteen consecutive samples in one cell: each coefficient
/// is loaded once for both halves.
__attribute__((target("avx2,fma"))) inline void cell_fir16(const float* x, const float* a, __m256 u0, __m256 u1,
                                                           float* out) {
  __m256 p0 = _mm256_setzero_ps(), p1 = p0, p2 = p0, q0 = p0, q1 = p0, q2 = p0;
  for (std::size_t t = 0; t < kTaps; ++t) {
    const __m256 xp = _mm256_loadu_ps(x + t), xq = _mm256_loadu_ps(x + t + 8);
    const __m256 c0 = _mm256_broadcast_ss(a + t), c1 = _mm256_broadcast_ss(a + kTaps + t),
                 c2 = _mm256_broadcast_ss(a + 2 * kTaps + t);
    p0 = _mm256_fmadd_ps(c0, xp, p0);
    p1 = _mm256_fmadd_ps(c1, xp, p1);
    p2 = _mm256_fmadd_ps(c2, xp, p2);
    q0 = _mm256_fmadd_ps(c0, xq, q0);
    q1 = _mm256_fmadd_ps(c1, xq, q1);
    q2 = _mm256_fmadd_ps(c2, xq, q2);
  }
  _mm256_storeu_ps(out, _mm256_fmadd_ps(u0, _mm256_fmadd_ps(u0, p2, p1), p0));
  _mm256_storeu_ps(out + 8, _mm256_fmadd_ps(u1, _mm256_fmadd_ps(u1, q2, q1), q0));
}

/// Eight samples each with its own kernel (a fast glide crossing many
/// cells): one 8-lane product per sample, then the eight vectors transposed
/// and summed together (three rounds of horizontal adds).
__attribute__((target("avx2,fma"))) void glide_each(const Glide& g, std::size_t i0, float* out) {
  __m256 s[8];
  for (std::size_t j = 0; j < 8; ++j) {
    const std::int64_t pos = walk(g, i0 + j), cell = pos >> kUBits;
    const float* x = window(g, i0 + j, cell);
    const float* a = coefficients(g, cell);
    const __m256 u = _mm256_set1_ps(static_cast<float>(pos & kUMask) * kUScale);
    const __m256 lo = _mm256_fmadd_ps(u, _mm256_fmadd_ps(u, _mm256_loadu_ps(a + 32), _mm256_loadu_ps(a + 16)), _mm256_loadu_ps(a));
    const __m256 hi = _mm256_fmadd_ps(u, _mm256_fmadd_ps(u, _mm256_loadu_ps(a + 40), _mm256_loadu_ps(a + 24)), _mm256_loadu_ps(a + 8));
    s[j] = _mm256_fmadd_ps(hi, _mm256_loadu_ps(x + 8), _mm256_mul_ps(lo, _mm256_loadu_ps(x)));
  }
  const __m256 t0 = _mm256_hadd_ps(s[0], s[1]), t1 = _mm256_hadd_ps(s[2], s[3]);
  const __m256 t2 = _mm256_hadd_ps(s[4], s[5]), t3 = _mm256_hadd_ps(s[6], s[7]);
  const __m256 u0 = _mm256_hadd_ps(t0, t1), u1 = _mm256_hadd_ps(t2, t3);  // halves of samples 0-3, 4-7
  _mm256_storeu_ps(out + i0, _mm256_add_ps(_mm256_permute2f128_ps(u0, u1, 0x20), _mm256_permute2f128_ps(u0, u1, 0x31)));
}

/// Eight samples' positions from `first` (steps: 0..7 steps), relative to
/// the start of `cell`: they fit 32 bits while they lie within a few cells.
__attribute__((target("avx2,fma"))) inline __m256i relative(std::int64_t first, std::int64_t cell, __m256i steps) {
  return _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(first - (cell << kUBits)))), steps);
}
/// Their places u (0..1) within their cells.
__attribute__((target("avx2,fma"))) inline __m256 place(std::int64_t first, std::int64_t cell, __m256i steps) {
  const __m256i rel = relative(first, cell, steps);
  return _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(rel, _mm256_set1_epi32(static_cast<int>(kUMask)))),
                       _mm256_set1_ps(kUScale));
}
/// The walk eight samples at a time. A delay moves slowly against a cell
/// (1/32 sample): sixteen samples often share one cell (cell_fir16), a
/// group of eight mostly does, sometimes spanning two or three. Each cell
/// in such a group runs cell_fir over all eight samples and keeps the lanes
/// that are in it; a group spanning more cells (a fast Doppler glide) takes
/// glide_each.
constexpr std::int64_t kMaxCellsPerGroup = 3;
__attribute__((target("avx2,fma"))) void glide_avx2(const Glide& g, float* out, std::size_t n) {
  const auto st = static_cast<std::uint32_t>(g.step);
  const __m256i steps = _mm256_mullo_epi32(_mm256_set1_epi32(static_cast<int>(st)), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256i u_mask = _mm256_set1_epi32(static_cast<int>(kUMask));
  const __m256 u_scale = _mm256_set1_ps(kUScale);
  std::size_t i0 = 0;
  for (; i0 + 8 <= n; i0 += 8) {
    const std::int64_t first = walk(g, i0), last = walk(g, i0 + 7);
    if (i0 + 16 <= n) {  // sixteen samples in one cell (the walk is linear: its ends decide)
      const std::int64_t cell = first >> kUBits;
      if (cell == walk(g, i0 + 15) >> kUBits) {
        cell_fir16(window(g, i0, cell), coefficients(g, cell), place(first, cell, steps), place(walk(g, i0 + 8), cell, steps), out + i0);
        i0 += 8;
        continue;
      }
    }
    const std::int64_t lo = std::min(first, last) >> kUBits, hi = std::max(first, last) >> kUBits;
    if (hi - lo >= kMaxCellsPerGroup) {
      glide_each(g, i0, out);
      continue;
    }
    const __m256i rel = relative(first, lo, steps);
    const __m256 u = _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_and_si256(rel, u_mask)), u_scale);
    __m256 y = cell_fir(window(g, i0, lo), coefficients(g, lo), u);
    if (hi != lo) {
      const __m256i lane_cell = _mm256_srli_epi32(rel, kUBits);  // 0 .. hi - lo
      for (std::int64_t c = lo + 1; c <= hi; ++c) {
        const __m256 yc = cell_fir(window(g, i0, c), coefficients(g, c), u);
        const __m256i in_c = _mm256_cmpeq_epi32(lane_cell, _mm256_set1_epi32(static_cast<int>(c - lo)));
        y = _mm256_blendv_ps(y, yc, _mm256_castsi256_ps(in_c));
      }
    }
    _mm256_storeu_ps(out + i0, y);
  }
  for (; i0 < n; ++i0) out[i0] = glide_sample(g, i0);
}
#endif

}  // namespace

FractionalDelay::FractionalDelay(std::size_t block, double max_delay_samples, bool portable)
    : max_delay_(std::max(kMinDelay, max_delay_samples)), kernels_(kernel_table().data()) {
  size_ = std::bit_ceil(block + static_cast<std::size_t>(std::ceil(max_delay_)) + kMirror + 2);
  ring_.assign(size_ + kMirror, 0.0f);
#ifdef EARSHOT_DELAY_AVX2
  avx2_ = !portable && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  (void)portable;
#endif
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
  const Glide g{ring_.data(), mask, block_start + size_ - static_cast<std::size_t>(kHalf), pos0, pos_step, kernels_};
#ifdef EARSHOT_DELAY_AVX2
  if (avx2_) return glide_avx2(g, out.data(), n);
#endif
  glide_generic(g, out.data(), n);
}

}  // namespace earshot::audio
