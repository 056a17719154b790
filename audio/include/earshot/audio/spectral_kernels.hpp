// The renderer's innermost loops, mostly over partitioned spectra in planar layout
// (a partition of S bins is S real parts, then S imaginary parts: plain
// vertical arithmetic that vectorises without shuffles). Each call runs the
// kernel of the instruction set chosen once for this process (AVX2+FMA or
// baseline: simd_kernels.hpp). Pointers may not overlap; S (bins) must be a
// multiple of 8.
#pragma once

#include <complex>
#include <cstddef>
#include <cstdint>

namespace earshot::audio::kernels {

/// acc += x * h over one partition of S bins.
void multiply_add(const float* x, const float* h, float* acc, std::size_t S);

/// The same with h stored as 16-bit integers times `scale`.
void multiply_add_scaled(const float* x, const std::int16_t* h, float scale, float* acc, std::size_t S);

/// out += (c0 + c1 r[i] + c2 r2[i]) * x[i] over n samples, r2 = r^2 (a gain
/// curve across a block; n need not be a multiple of 8).
void add_shaped(const float* x, float c0, float c1, float c2, const float* r, const float* r2, float* out,
                std::size_t n);

/// Interleaved complex (n values) to planar (re[0..S), im[0..S)), S >= n;
/// the padding bins are left as they are.
void to_planar(const std::complex<float>* in, std::size_t n, float* out, std::size_t S);
/// The same with the odd bins negated: the spectrum of the input rotated
/// by half the FFT size (overlap-save windows whose halves alternate).
void to_planar_odd_negated(const std::complex<float>* in, std::size_t n, float* out, std::size_t S);
/// Planar back to interleaved complex (n values).
void to_interleaved(const float* in, std::size_t S, std::complex<float>* out, std::size_t n);

}  // namespace earshot::audio::kernels
