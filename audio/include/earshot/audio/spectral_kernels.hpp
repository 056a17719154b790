// The renderer's innermost loops over partitioned spectra in planar layout
// (a partition of S bins is S real parts, then S imaginary parts: plain
// vertical arithmetic that vectorises without shuffles). Compiled twice
// (AVX2+FMA and baseline x86-64) and picked at load time for the CPU that
// runs them. Pointers may not overlap; S (bins) must be a multiple of 8.
#pragma once

#include <complex>
#include <cstddef>

namespace earshot::audio::kernels {

/// acc += x * h over one partition of S bins.
void multiply_add(const float* x, const float* h, float* acc, std::size_t S);

/// acc_a += x * a and acc_b += x * b in one pass over x (a filter crossfade).
void multiply_add2(const float* x, const float* a, const float* b, float* acc_a, float* acc_b, std::size_t S);

/// out = w0 s0 + w1 s1 + w2 s2 over n floats (a blend of three measured spectra)
void blend3(const float* s0, const float* s1, const float* s2, float w0, float w1, float w2, float* out,
            std::size_t n);

/// x *= g over n floats
void scale(float* x, float g, std::size_t n);

/// Interleaved complex (n values) to planar (re[0..S), im[0..S)), S >= n;
/// the padding bins are left as they are.
void to_planar(const std::complex<float>* in, std::size_t n, float* out, std::size_t S);
/// Planar back to interleaved complex (n values).
void to_interleaved(const float* in, std::size_t S, std::complex<float>* out, std::size_t n);

}  // namespace earshot::audio::kernels
