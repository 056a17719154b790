// The inner product of two float runs, summed in eight interleaved partial
// sums: the compiler turns that into vector code without -ffast-math (a
// single running sum must be added in order, so it stays scalar). Load-time
// FIR loops (resampling, the onset split) spend their time here.
#pragma once

#include <array>
#include <cstddef>

namespace earshot::hrtf::detail {

inline float dot(const float* a, const float* b, std::size_t n) {
  std::array<float, 8> acc{};
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8)
    for (std::size_t k = 0; k < 8; ++k) acc[k] += a[i + k] * b[i + k];
  float tail = 0.0f;
  for (; i < n; ++i) tail += a[i] * b[i];
  return ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) + tail;
}

}  // namespace earshot::hrtf::detail
