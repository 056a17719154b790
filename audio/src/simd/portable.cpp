// The kernels for the baseline instruction set (what the compiler
// vectorises for the target with no extra flags): always built, always
// runnable, the reference the vector files are tested against.
#include <array>

#include "glide.hpp"
#include "spectral_loops.hpp"
#include "tables.hpp"

namespace earshot::audio::simd {

float glide_sample_portable(const Glide& g, std::size_t i) {
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

namespace {
void glide(const Glide& g, float* out, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out[i] = glide_sample_portable(g, i);
}
}  // namespace

constinit const Kernels portable_kernels{
    Isa::portable, multiply_add, multiply_add_scaled, add_shaped, to_planar, to_planar_odd_negated, to_interleaved,
    real_spectrum, glide, fir_glide,
};

}  // namespace earshot::audio::simd
