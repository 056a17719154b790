// The renderer's innermost loops, mostly over partitioned spectra in planar layout
// (a partition of S bins is S real parts, then S imaginary parts: plain
// vertical arithmetic that vectorises without shuffles). Each call runs the
// kernel of the instruction set chosen once for this process (AVX2+FMA or
// baseline: simd_kernels.hpp, the loops in audio/src/simd/). Pointers may not
// overlap; S (bins) must be a multiple of 8.
#pragma once

#include <complex>
#include <cstddef>
#include <cstdint>

#include "earshot/audio/simd_kernels.hpp"

namespace earshot::audio::kernels {

/// acc += x * h over one partition of S bins.
inline void multiply_add(const float* x, const float* h, float* acc, std::size_t S) {
  simd::kernels().multiply_add(x, h, acc, S);
}

/// The same with h stored as 16-bit integers times `scale`.
inline void multiply_add_scaled(const float* x, const std::int16_t* h, float scale, float* acc, std::size_t S) {
  simd::kernels().multiply_add_scaled(x, h, scale, acc, S);
}

/// y[i] = a[i] + (i + 1) / n (b[i] - a[i]), a = h0 * x, b = h1 * x (T-tap
/// FIRs; x[i - k] readable for k < T; h1 may equal h0). n need not be a
/// multiple of 8.
inline void fir_glide(const float* h0, const float* h1, std::size_t T, const float* x, float* y, std::size_t n) {
  simd::kernels().fir_glide(h0, h1, T, x, y, n);
}

/// out += (c0 + c1 r[i] + c2 r2[i]) * x[i] over n samples, r2 = r^2 (a gain
/// curve across a block; n need not be a multiple of 8).
inline void add_shaped(const float* x, float c0, float c1, float c2, const float* r, const float* r2, float* out,
                       std::size_t n) {
  simd::kernels().add_shaped(x, c0, c1, c2, r, r2, out, n);
}

/// Interleaved complex (n values) to planar (re[0..S), im[0..S)), S >= n;
/// the padding bins are left as they are.
inline void to_planar(const std::complex<float>* in, std::size_t n, float* out, std::size_t S) {
  simd::kernels().to_planar(in, n, out, S);
}
/// The same with the odd bins negated: the spectrum of the input rotated
/// by half the FFT size (overlap-save windows whose halves alternate).
inline void to_planar_odd_negated(const std::complex<float>* in, std::size_t n, float* out, std::size_t S) {
  simd::kernels().to_planar_odd_negated(in, n, out, S);
}
/// The last step of a real FFT of 2M samples done as a complex FFT of M
/// (z_n = x_2n + i x_2n+1): from its output z (M + 1 values, z[M] = z[0])
/// to the real signal's M + 1 bins, planar into out (re[0..S), im[0..S)),
/// bin k times sign[k]; c[k] = cos(pi k / M) / 2, s[k] = sin(pi k / M) / 2.
/// Vectorised (the library's own last step is scalar code).
inline void real_spectrum(const std::complex<float>* z, std::size_t M, const float* c, const float* s,
                          const float* sign, float* out, std::size_t S) {
  simd::kernels().real_spectrum(z, M, c, s, sign, out, S);
}
/// Planar back to interleaved complex (n values).
inline void to_interleaved(const float* in, std::size_t S, std::complex<float>* out, std::size_t n) {
  simd::kernels().to_interleaved(in, S, out, n);
}

}  // namespace earshot::audio::kernels
