// The inner product of two float runs, summed in eight interleaved partial
// sums: the compiler turns that into vector code without -ffast-math (a
// single running sum must be added in order, so it stays scalar). Load-time
// FIR loops (resampling, the onset split) spend their time here.
#pragma once

#include <array>
#include <cstddef>
#include <span>

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

/// The same in double (energies and Gram entries, where float sums drift),
/// four partial sums.
inline double dot_double(std::span<const float> a, std::span<const float> b) {
  std::array<double, 4> acc{};
  std::size_t i = 0;
  for (; i + 4 <= a.size(); i += 4)
    for (std::size_t k = 0; k < 4; ++k) acc[k] += double(a[i + k]) * b[i + k];
  for (; i < a.size(); ++i) acc[0] += double(a[i]) * b[i];
  return (acc[0] + acc[1]) + (acc[2] + acc[3]);
}

}  // namespace earshot::hrtf::detail
