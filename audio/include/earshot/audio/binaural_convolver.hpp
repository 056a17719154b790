// One mono signal through a left and a right filter: uniformly partitioned
// overlap-save convolution (block B, FFT 2B, one input spectrum history
// shared by both ears). A DSP unit the Resonance way: everything is
// allocated at construction; set_filters() and process() never allocate.
//
// A filter change is crossfaded over one block: the block after
// set_filters() is computed with the old and the new filters and blended
// linearly, so a moving source never clicks.
#pragma once

#include <array>
#include <complex>
#include <span>
#include <vector>

#include "earshot/audio/real_fft.hpp"

namespace earshot::audio {

class BinauralConvolver {
 public:
  /// block: samples per process() call; max_filter_length: longest filter.
  BinauralConvolver(std::size_t block, std::size_t max_filter_length);

  /// New filters (each at most max_filter_length; shorter ones are zero-
  /// padded). The first call takes effect at once; later ones crossfade
  /// during the next process().
  void set_filters(std::span<const float> left, std::span<const float> right);

  /// New filters given as partitioned spectra (as HrtfSpectra holds them):
  /// write partitions() * (block() + 1) bins per ear into the two spans, then
  /// call end_filter_update(). Same effect as set_filters; no FFT.
  [[nodiscard]] std::array<std::span<std::complex<float>>, 2> begin_filter_update();
  void end_filter_update();

  /// One block: `in` and both outputs hold block() samples.
  void process(std::span<const float> in, std::span<float> left, std::span<float> right);

  /// Forget the signal history (filters are kept).
  void reset();

  [[nodiscard]] std::size_t block() const { return block_; }
  [[nodiscard]] std::size_t partitions() const { return parts_; }

 private:
  using Spectrum = std::vector<std::complex<float>>;
  void transform_filter(std::span<const float> ir, std::span<std::complex<float>> bank);
  void convolve(const Spectrum& bank, std::span<float> out);

  std::size_t block_, parts_, bins_;
  RealFft fft_;
  std::vector<float> input_;   // 2B: previous block then current block
  Spectrum history_;           // parts_ input spectra, newest at head_
  std::size_t head_ = 0;
  Spectrum filters_[2][2];     // [bank][ear], parts_ * bins_ each
  int current_ = 0;
  bool pending_ = false, have_filters_ = false;
  Spectrum acc_;
  std::vector<float> time_, old_out_, padded_;
};

}  // namespace earshot::audio
