#include "earshot/audio/spectral_kernels.hpp"

#include "earshot/audio/simd_kernels.hpp"

// The named kernels: each runs the chosen instruction set's (simd/*.cpp).
namespace earshot::audio::kernels {

void multiply_add(const float* x, const float* h, float* acc, std::size_t S) {
  simd::kernels().multiply_add(x, h, acc, S);
}

void multiply_add_scaled(const float* x, const std::int16_t* h, float scale, float* acc, std::size_t S) {
  simd::kernels().multiply_add_scaled(x, h, scale, acc, S);
}

void add_shaped(const float* x, float c0, float c1, float c2, const float* r, const float* r2, float* out,
                std::size_t n) {
  simd::kernels().add_shaped(x, c0, c1, c2, r, r2, out, n);
}

void to_planar(const std::complex<float>* in, std::size_t n, float* out, std::size_t S) {
  simd::kernels().to_planar(in, n, out, S);
}

void to_planar_odd_negated(const std::complex<float>* in, std::size_t n, float* out, std::size_t S) {
  simd::kernels().to_planar_odd_negated(in, n, out, S);
}

void to_interleaved(const float* in, std::size_t S, std::complex<float>* out, std::size_t n) {
  simd::kernels().to_interleaved(in, S, out, n);
}

}  // namespace earshot::audio::kernels
