// Every measured HRTF filter of a set, pre-transformed into the partitioned
// spectra the BinauralConvolver multiplies by (block B: partitions of B taps,
// each zero-padded to 2B and transformed). Blending three measurements for a
// new direction is then a weighted sum of spectra: no FFT on the audio
// thread when a source or the head moves. Built once per set and block size;
// immutable afterwards, so renderers may share one.
#pragma once

#include <complex>
#include <span>
#include <vector>

#include "earshot/hrtf/hrtf_set.hpp"

namespace earshot::audio {

class HrtfSpectra {
 public:
  HrtfSpectra(const hrtf::HrtfSet& set, std::size_t block);

  [[nodiscard]] std::size_t block() const { return block_; }
  [[nodiscard]] std::size_t partitions() const { return parts_; }
  [[nodiscard]] std::size_t bins() const { return block_ + 1; }
  /// partitions() * bins() values: partition p's bins at [p * bins(), (p + 1) * bins()).
  [[nodiscard]] std::span<const std::complex<float>> spectrum(std::size_t measurement, hrtf::Ear ear) const;

  /// Energy (sum of squared taps) of a filter given as such spectra
  /// (Parseval over the real FFT's half spectrum).
  [[nodiscard]] double energy(std::span<const std::complex<float>> spectra) const;

 private:
  std::size_t block_, parts_;
  std::vector<std::complex<float>> data_;  // [measurement][ear][partition][bin]
};

}  // namespace earshot::audio
