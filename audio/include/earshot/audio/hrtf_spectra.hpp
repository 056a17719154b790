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
#include <cstdint>
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
  /// The first partition (2 * stride() floats, planar as above): the head
  /// of the response, with nearly all of its energy, kept in float.
  [[nodiscard]] std::span<const float> head(std::size_t measurement, hrtf::Ear ear) const;
  /// Partitions 1 .. partitions() - 1, (partitions() - 1) * 2 * stride()
  /// values, as IEEE half floats (half_float.hpp). The bank streams every
  /// spectrum each block, so fewer bytes is speed; the tail is 25 dB or more
  /// below the head (MIT KEMAR), so the halves' rounding (-66 dB of each
  /// value, a little of it leaking past the partition as overlap-save
  /// aliasing) stays far below anything audible.
  [[nodiscard]] std::span<const std::uint16_t> tail(std::size_t measurement, hrtf::Ear ear) const;

 private:
  std::size_t block_, parts_, measurements_;
  AlignedVector<float> head_;          // [measurement][ear][re, im][stride]
  AlignedVector<std::uint16_t> tail_;  // [measurement][ear][partition - 1][re, im][stride], half floats
};

}  // namespace earshot::audio
