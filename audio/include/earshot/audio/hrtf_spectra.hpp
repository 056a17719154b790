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

  /// The version of what the constructor computes: bump it with any change
  /// that changes its arrays (the FFT, the layout, the quantisation), so
  /// spectra kept on disk by an older build are computed again
  /// (earshot/audio/hrtf_disk_cache.hpp).
  static constexpr std::uint32_t kPreparationVersion = 1;

  /// The arrays, for a disk cache: head, tail and scales as laid out below.
  struct Stored {
    std::size_t block = 0;
    AlignedVector<float> head;
    AlignedVector<std::int16_t> tail;
    std::vector<float> scale;
  };
  [[nodiscard]] Stored stored() const;
  /// The spectra `stored()` gave for `set`, taken back without the FFTs.
  /// Throws std::invalid_argument when a size does not fit `set` and the
  /// block, or a value is not finite.
  HrtfSpectra(const hrtf::HrtfSet& set, Stored stored);

  [[nodiscard]] std::size_t block() const { return block_; }
  [[nodiscard]] std::size_t partitions() const { return parts_; }
  [[nodiscard]] std::size_t measurements() const { return measurements_; }
  [[nodiscard]] std::size_t bins() const { return block_ + 1; }
  [[nodiscard]] std::size_t stride() const { return partition_stride(block_); }
  /// The first partition (2 * stride() floats, planar as above): the head
  /// of the response, with nearly all of its energy, kept in float.
  [[nodiscard]] std::span<const float> head(std::size_t measurement, hrtf::Ear ear) const;
  /// Partitions 1 .. partitions() - 1, (partitions() - 1) * 2 * stride()
  /// values, as 16-bit integers: partition p's values are tail()[..] times
  /// tail_scale(m, ear)[p - 1]. The bank streams every spectrum each block,
  /// so fewer bytes is speed. One scale per partition fits its largest
  /// value, so the rounding sits about 90 dB below the partition (and the
  /// tail is 25 dB or more below the head for MIT KEMAR). Half floats
  /// (-66 dB of each value) were tried: their rounding leaks past the
  /// partition's zero-padded half as overlap-save aliasing, which repeats
  /// with the block and put block-rate sidebands 94 dB down on a still tone.
  [[nodiscard]] std::span<const std::int16_t> tail(std::size_t measurement, hrtf::Ear ear) const;
  [[nodiscard]] std::span<const float> tail_scale(std::size_t measurement, hrtf::Ear ear) const;
 private:
  static constexpr std::size_t kMaxStoredBlock = std::size_t{1} << 20;  // keeps the size products small
  std::size_t block_, parts_, measurements_;
  AlignedVector<float> head_;          // [measurement][ear][re, im][stride]
  AlignedVector<std::int16_t> tail_;  // [measurement][ear][partition - 1][re, im][stride], scaled
  std::vector<float> scale_;          // [measurement][ear][partition - 1]
};

}  // namespace earshot::audio
