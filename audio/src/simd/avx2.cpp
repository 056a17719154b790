// The kernels for AVX2 + FMA. This file alone is compiled with -mavx2 -mfma
// (audio/CMakeLists.txt) and runs only where dispatch.cpp found both.
//
// No inline functions or templates from other headers here (std::min and
// the like): a copy of one built with these flags could be the copy the
// linker keeps for baseline code. The shared helpers have internal linkage.
#include <immintrin.h>

#define EARSHOT_SIMD_OWN_REAL_SPECTRUM  // defined below, by hand
#include "glide.hpp"
#include "spectral_loops.hpp"
#include "tables.hpp"

namespace earshot::audio::simd {
namespace {

/// Eight consecutive samples whose kernels all lie in one cell with one
/// whole delay: the three polynomial coefficients' FIRs, run across the
/// eight samples at once (lane j reads x[j + t]), then a0 + u (a1 + u a2)
/// per lane. Even and odd taps sum apart to halve the dependency chains.
inline __m256 cell_fir(const float* x, const float* a, __m256 u) {
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
inline void cell_fir16(const float* x, const float* a, __m256 u0, __m256 u1, float* out) {
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
void glide_each(const Glide& g, std::size_t i0, float* out) {
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
inline __m256i relative(std::int64_t first, std::int64_t cell, __m256i steps) {
  return _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(first - (cell << kUBits)))), steps);
}
/// Their places u (0..1) within their cells.
inline __m256 place(std::int64_t first, std::int64_t cell, __m256i steps) {
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
void glide(const Glide& g, float* out, std::size_t n) {
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
    const std::int64_t lo = (first < last ? first : last) >> kUBits, hi = (first < last ? last : first) >> kUBits;
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
  for (; i0 < n; ++i0) out[i0] = glide_sample_portable(g, i0);
}

/// Eight interleaved complex values from p: their real and imaginary parts.
inline void deinterleave(const float* p, __m256& re, __m256& im) {
  const __m256 a = _mm256_loadu_ps(p), b = _mm256_loadu_ps(p + 8);
  // Per 128-bit half: a0 a1 b0 b1 | a2 a3 b2 b3 (as complex indices), then the quarters put in order.
  re = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(a, b, 0x88)), 0xD8));
  im = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(_mm256_shuffle_ps(a, b, 0xDD)), 0xD8));
}

/// real_spectrum with bins k and M - k read eight at a time: gcc does not
/// vectorise the reversed, interleaved reads of the plain loop well.
void real_spectrum(const std::complex<float>* zc, std::size_t M, const float* __restrict c, const float* __restrict s,
                   const float* __restrict sign, float* __restrict out, std::size_t S) {
  const float* z = reinterpret_cast<const float*>(zc);
  std::size_t k = 0;
  if (M % 8 == 0) {
    const __m256i reverse = _mm256_setr_epi32(7, 6, 5, 4, 3, 2, 1, 0);
    const __m256 half = _mm256_set1_ps(0.5f);
    for (; k < M; k += 8) {
      __m256 ar, ai, br, bi;
      deinterleave(z + 2 * k, ar, ai);
      deinterleave(z + 2 * (M - k - 7), br, bi);  // bins M - k - 7 .. M - k, then reversed
      br = _mm256_permutevar8x32_ps(br, reverse);
      bi = _mm256_permutevar8x32_ps(bi, reverse);
      const __m256 dr = _mm256_sub_ps(ar, br), di = _mm256_add_ps(ai, bi);
      const __m256 ck = _mm256_loadu_ps(c + k), sk = _mm256_loadu_ps(s + k), g = _mm256_loadu_ps(sign + k);
      // re = (ar + br)/2 + c di - s dr;  im = (ai - bi)/2 - c dr - s di
      __m256 re = _mm256_fmadd_ps(ck, di, _mm256_mul_ps(half, _mm256_add_ps(ar, br)));
      re = _mm256_fnmadd_ps(sk, dr, re);
      __m256 im = _mm256_fnmadd_ps(ck, dr, _mm256_mul_ps(half, _mm256_sub_ps(ai, bi)));
      im = _mm256_fnmadd_ps(sk, di, im);
      _mm256_storeu_ps(out + k, _mm256_mul_ps(g, re));
      _mm256_storeu_ps(out + S + k, _mm256_mul_ps(g, im));
    }
  }
  for (; k <= M; ++k) real_spectrum_bin(z, M, k, c, s, sign, out, S);
}

}  // namespace

constinit const Kernels avx2_kernels{
    Isa::avx2, multiply_add, multiply_add_scaled, add_shaped, to_planar, to_planar_odd_negated, to_interleaved,
    real_spectrum, glide, fir_glide,
};

}  // namespace earshot::audio::simd
