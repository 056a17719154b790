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
