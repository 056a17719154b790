// The frequency-domain sum of every source's binaural output in one block.
// Convolution is linear, so instead of one inverse FFT per source and ear
// the convolvers add their spectra here and the bus runs the inverse FFTs
// once per ear: a source's cost is then its forward FFTs and its
// multiply-adds, whatever the number of sources.
//
// A filter change is crossfaded over one block. The crossfade is the same
// ramp for every source, so it too can be summed before the inverse FFT:
// steady sources add into one accumulator per ear, changing sources add
// their old filters' output into a fading-out and their new filters' into a
// fading-in accumulator; mix_into() blends the three. At most six inverse
// FFTs per block, however many sources move.
//
// A DSP unit the Resonance way: allocated at construction, never after.
#pragma once

#include <array>
#include <complex>
#include <span>

#include "earshot/audio/aligned_vector.hpp"
#include "earshot/audio/real_fft.hpp"

namespace earshot::audio {

class BinauralBus {
 public:
  enum class Fade { steady = 0, out = 1, in = 2 };

  explicit BinauralBus(std::size_t block);

  [[nodiscard]] std::size_t block() const { return block_; }
  /// The 2 * block FFT the convolvers share (single-threaded, like the bus).
  [[nodiscard]] const RealFft& fft() const { return fft_; }

  /// Start a block: every accumulator empty.
  void clear();
  /// One ear's accumulator for one fade (one planar partition of
  /// 2 * partition_stride(block) floats, as HrtfSpectra lays them out); marks it used.
  [[nodiscard]] float* accumulator(std::size_t ear, Fade fade);
  /// Inverse FFTs of the used accumulators, the last block samples of each
  /// (overlap-save), crossfaded, added into left and right.
  void mix_into(std::span<float> left, std::span<float> right);

 private:
  std::size_t block_;
  RealFft fft_;
  std::array<std::array<AlignedVector<float>, 3>, 2> acc_;  // [ear][fade], planar
  AlignedVector<std::complex<float>> spectrum_;             // an accumulator interleaved for the inverse FFT
  std::array<std::array<bool, 3>, 2> used_{};
  AlignedVector<float> time_;
  AlignedVector<float> ramp_;  // (i + 1) / block
};

}  // namespace earshot::audio
