// One source's two ear signals through a left and a right filter: uniformly
// partitioned overlap-save convolution (block B, FFT 2B), each ear with its
// own input (the ears hear the source at different delays). The products
// are not transformed back here: they are added into a BinauralBus, which
// runs the inverse FFTs once for all sources. A DSP unit the Resonance way:
// everything is allocated at construction; process() never allocates.
//
// A filter change is crossfaded over one block: the block after a filter
// update adds the old filters' output to the bus's fading-out accumulator
// and the new filters' to its fading-in one, so a moving source never
// clicks.
#pragma once

#include <array>
#include <complex>
#include <span>

#include "earshot/audio/aligned_vector.hpp"
#include "earshot/audio/binaural_bus.hpp"
#include "earshot/audio/real_fft.hpp"

namespace earshot::audio {

class BinauralConvolver {
 public:
  /// block: samples per process() call; max_filter_length: longest filter.
  BinauralConvolver(std::size_t block, std::size_t max_filter_length);

  /// New filters as impulse responses (each at most max_filter_length;
  /// shorter ones are zero-padded), transformed with `fft` (size 2 * block).
  /// The first call takes effect at once; later ones crossfade during the
  /// next process().
  void set_filters(std::span<const float> left, std::span<const float> right, const RealFft& fft);

  /// New filters given as partitioned spectra in HrtfSpectra's planar
  /// layout: write partitions() * 2 * partition_stride(block()) floats per
  /// ear into the two spans, then call end_filter_update(). Same effect as
  /// set_filters; no FFT.
  [[nodiscard]] std::array<std::span<float>, 2> begin_filter_update();
  void end_filter_update();

  /// One block: each ear's input (block() samples) through that ear's
  /// filter, added into `bus` (whose block must match).
  void process(std::span<const float> left_in, std::span<const float> right_in, BinauralBus& bus);

  /// Forget the signal history (filters are kept).
  void reset();

  [[nodiscard]] std::size_t block() const { return block_; }
  [[nodiscard]] std::size_t partitions() const { return parts_; }

 private:
  using Spectrum = AlignedVector<float>;  // planar partitions

  std::size_t block_, parts_, stride_;
  std::array<AlignedVector<float>, 2> input_;  // per ear, 2B: previous block then current block
  std::array<Spectrum, 2> history_;            // per ear, parts_ input spectra, newest at head_
  std::size_t head_ = 0;
  AlignedVector<float> padded_;  // set_filters' scratch: one partition zero-padded to 2B
  AlignedVector<std::complex<float>> spectrum_;  // one FFT's output, before it goes planar
  Spectrum filters_[2][2];  // [bank][ear], parts_ * stride_ each
  int current_ = 0;
  bool pending_ = false, have_filters_ = false;
};

}  // namespace earshot::audio
