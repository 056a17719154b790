// Every measured HRTF filter of a set, pre-transformed into the partitioned
// spectra that the DirectionBank's convolvers multiply by (block B:
// partitions of B taps, each zero-padded to 2B and transformed): no FFT of a
// filter on the audio thread. Built once per set and block size; immutable
// afterwards, so renderers may share one.
//
// Layout (the bank's histories and accumulators too): planar. Partition p takes
// 2 * stride() floats from p * 2 * stride(): the real parts of its B + 1
// bins, then their imaginary parts, each run padded with zeros to stride()
// (B + 1 rounded up to a multiple of 8 floats), so every run is aligned for
// SIMD and the multiply-adds need no shuffles.
#pragma once

#include <complex>
#include <span>
#include <vector>

#include "earshot/audio/aligned_vector.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace earshot::audio {

/// Bins per partition in the padded planar layout: B + 1 rounded up to a
/// multiple of 8 floats (32 bytes). A partition is 2 * stride floats.
[[nodiscard]] constexpr std::size_t partition_stride(std::size_t block) { return (block + 1 + 7) / 8 * 8; }

class HrtfSpectra {
 public:
  HrtfSpectra(const hrtf::HrtfSet& set, std::size_t block);

  [[nodiscard]] std::size_t block() const { return block_; }
  [[nodiscard]] std::size_t partitions() const { return parts_; }
  [[nodiscard]] std::size_t measurements() const { return measurements_; }
  [[nodiscard]] std::size_t bins() const { return block_ + 1; }
  [[nodiscard]] std::size_t stride() const { return partition_stride(block_); }
  /// partitions() * 2 * stride() floats in the planar layout above.
  [[nodiscard]] std::span<const float> spectrum(std::size_t measurement, hrtf::Ear ear) const;

 private:
  std::size_t block_, parts_, measurements_;
  AlignedVector<float> data_;  // [measurement][ear][partition][re, im][stride]
};

}  // namespace earshot::audio
