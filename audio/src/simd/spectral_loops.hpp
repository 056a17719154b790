// The spectral kernels as plain loops, written once and compiled once per
// instruction set: each file that includes this (portable.cpp, avx2.cpp)
// lets the compiler vectorise them with its own flags. Their contracts are
// in earshot/audio/spectral_kernels.hpp.
//
// Internal linkage (the unnamed namespace), so each file keeps its own
// copy: the linker can never hand baseline code a copy built for AVX2.
#pragma once

#include <complex>
#include <cstddef>
#include <cstdint>

namespace earshot::audio::simd {
namespace {

void multiply_add(const float* __restrict x, const float* __restrict h, float* __restrict acc, std::size_t S) {
  const float *xr = x, *xi = x + S, *hr = h, *hi = h + S;
  float *ar = acc, *ai = acc + S;
  for (std::size_t k = 0; k < S; ++k) {
    ar[k] += xr[k] * hr[k] - xi[k] * hi[k];
    ai[k] += xr[k] * hi[k] + xi[k] * hr[k];
  }
}

void multiply_add_scaled(const float* __restrict x, const std::int16_t* __restrict h, float scale,
                         float* __restrict acc, std::size_t S) {
  const float *xr = x, *xi = x + S;
  const std::int16_t *hr = h, *hi = h + S;
  float *ar = acc, *ai = acc + S;
  for (std::size_t k = 0; k < S; ++k) {
    const float re = scale * static_cast<float>(hr[k]), im = scale * static_cast<float>(hi[k]);
    ar[k] += xr[k] * re - xi[k] * im;
    ai[k] += xr[k] * im + xi[k] * re;
  }
}

/// Outputs in groups of kFirGroup held in registers across all the taps (the
/// taps-outer loop it replaces loaded and stored the block once per tap),
/// both filters from the same loads of x.
constexpr std::size_t kFirGroup = 32;

void fir_glide(const float* h0, const float* h1, std::size_t T, const float* __restrict x,
               float* __restrict y, std::size_t n) {
  if (h0 == h1) {  // one filter: half the work
    for (std::size_t i0 = 0; i0 < n; i0 += kFirGroup) {
      const std::size_t m = n - i0 < kFirGroup ? n - i0 : kFirGroup;
      float a[kFirGroup] = {};
      if (m == kFirGroup) {  // a fixed count, so the group stays in registers
        for (std::size_t k = 0; k < T; ++k) {
          const float g = h0[k];
          const float* xk = x + i0 - k;
          for (std::size_t j = 0; j < kFirGroup; ++j) a[j] += g * xk[j];
        }
      } else {
        for (std::size_t k = 0; k < T; ++k) {
          const float g = h0[k];
          const float* xk = x + i0 - k;
          for (std::size_t j = 0; j < m; ++j) a[j] += g * xk[j];
        }
      }
      for (std::size_t j = 0; j < m; ++j) y[i0 + j] = a[j];
    }
    return;
  }
  const float step = 1.0f / static_cast<float>(n);
  for (std::size_t i0 = 0; i0 < n; i0 += kFirGroup) {
    const std::size_t m = n - i0 < kFirGroup ? n - i0 : kFirGroup;
    float a[kFirGroup] = {}, b[kFirGroup] = {};
    if (m == kFirGroup) {
      for (std::size_t k = 0; k < T; ++k) {
        const float g0 = h0[k], g1 = h1[k];
        const float* xk = x + i0 - k;
        for (std::size_t j = 0; j < kFirGroup; ++j) {
          a[j] += g0 * xk[j];
          b[j] += g1 * xk[j];
        }
      }
    } else {
      for (std::size_t k = 0; k < T; ++k) {
        const float g0 = h0[k], g1 = h1[k];
        const float* xk = x + i0 - k;
        for (std::size_t j = 0; j < m; ++j) {
          a[j] += g0 * xk[j];
          b[j] += g1 * xk[j];
        }
      }
    }
    for (std::size_t j = 0; j < m; ++j) {
      const float r = static_cast<float>(i0 + j + 1) * step;
      y[i0 + j] = a[j] + r * (b[j] - a[j]);
    }
  }
}

void add_shaped(const float* __restrict x, float c0, float c1, float c2, const float* __restrict r,
                const float* __restrict r2, float* __restrict out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] += (c0 + c1 * r[i] + c2 * r2[i]) * x[i];
}

void to_planar(const std::complex<float>* in, std::size_t n, float* __restrict out, std::size_t S) {
  const float* __restrict f = reinterpret_cast<const float*>(in);
  for (std::size_t k = 0; k < n; ++k) {
    out[k] = f[2 * k];
    out[S + k] = f[2 * k + 1];
  }
}

void to_planar_odd_negated(const std::complex<float>* in, std::size_t n, float* __restrict out, std::size_t S) {
  const float* __restrict f = reinterpret_cast<const float*>(in);
  for (std::size_t k = 0; k < n; ++k) {
    const float sign = (k & 1) ? -1.0f : 1.0f;
    out[k] = sign * f[2 * k];
    out[S + k] = sign * f[2 * k + 1];
  }
}

inline void real_spectrum_bin(const float* __restrict z, std::size_t M, std::size_t k, const float* __restrict c,
                              const float* __restrict s, const float* __restrict sign, float* __restrict out,
                              std::size_t S) {
  const float ar = z[2 * k], ai = z[2 * k + 1], br = z[2 * (M - k)], bi = z[2 * (M - k) + 1];
  const float dr = ar - br, di = ai + bi;
  out[k] = sign[k] * (0.5f * (ar + br) + c[k] * di - s[k] * dr);
  out[S + k] = sign[k] * (0.5f * (ai - bi) - c[k] * dr - s[k] * di);
}

#ifndef EARSHOT_SIMD_OWN_REAL_SPECTRUM
void real_spectrum(const std::complex<float>* zc, std::size_t M, const float* __restrict c, const float* __restrict s,
                   const float* __restrict sign, float* __restrict out, std::size_t S) {
  const float* z = reinterpret_cast<const float*>(zc);
  for (std::size_t k = 0; k <= M; ++k) real_spectrum_bin(z, M, k, c, s, sign, out, S);
}
#endif

void to_interleaved(const float* __restrict in, std::size_t S, std::complex<float>* out, std::size_t n) {
  float* __restrict f = reinterpret_cast<float*>(out);
  for (std::size_t k = 0; k < n; ++k) {
    f[2 * k] = in[k];
    f[2 * k + 1] = in[S + k];
  }
}

}  // namespace
}  // namespace earshot::audio::simd
