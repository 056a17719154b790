// FractionalDelay's read at a moving delay, as the instruction-set files
// see it: the walk through the ring and the layout of the coefficient table
// (audio/src/fractional_delay.cpp builds both).
//
// Everything here that is code has internal linkage (the unnamed namespace):
// each instruction set's file compiles its own copy with its own flags, so
// the linker can never hand baseline code a copy built for AVX2.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#include "earshot/audio/fractional_delay.hpp"
#include "earshot/audio/simd_kernels.hpp"

namespace earshot::audio::simd {

/// Sample i of a gliding read is at pos = pos0 + step (i + 1), in 32.32
/// fixed point samples of delay. The top bits past the whole samples name
/// the cell (pos >> kUBits counts cells from delay 0), the rest is u, the
/// place in the cell. Sample i's kernel starts at ring index
/// (base + i - whole) & mask; the ring repeats its start past its end, so
/// sixteen samples' kernels read on without wrapping.
struct Glide {
  const float* ring;
  std::size_t mask, base;
  std::int64_t pos0, step;
  const float* table;  // kCells cells of kCellStride floats
};

namespace {

constexpr std::size_t kTaps = FractionalDelay::kTaps;
constexpr std::size_t kCells = FractionalDelay::kCells;
/// A cell's three coefficient rows: tap t's kernel is a0[t] + u (a1[t] + u a2[t]).
constexpr std::size_t kCellStride = 3 * kTaps;
constexpr int kCellBits = std::countr_zero(kCells);
constexpr int kUBits = 32 - kCellBits;
constexpr std::int64_t kUMask = (std::int64_t{1} << kUBits) - 1;
constexpr float kUScale = 1.0f / static_cast<float>(std::int64_t{1} << kUBits);

inline std::int64_t walk(const Glide& g, std::size_t i) { return g.pos0 + g.step * static_cast<std::int64_t>(i + 1); }
/// Where the kernel of sample i starts when its cell (counted from delay 0) is `cell`.
inline const float* window(const Glide& g, std::size_t i, std::int64_t cell) {
  return g.ring + ((g.base + i - static_cast<std::size_t>(cell >> kCellBits)) & g.mask);
}
inline const float* coefficients(const Glide& g, std::int64_t cell) {
  return g.table + static_cast<std::size_t>(cell & (kCells - 1)) * kCellStride;
}

}  // namespace

/// One sample of the walk, the reference way (eight lane sums, then halved
/// pairwise), built for the baseline only (portable.cpp): the vector files
/// call it for the samples left after their last whole group.
float glide_sample_portable(const Glide& g, std::size_t i);

}  // namespace earshot::audio::simd
