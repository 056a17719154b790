// BinauralDecoder: an ambiX bus (ACN, SN3D, (N+1)^2 planar channels) to two
// ears, through the FIR filters of a decoder design
// (binaural_decoder_design.hpp).
//
// Uniformly partitioned overlap-save convolution (block B, FFT 2B), the
// frequency-domain delay line on the input side: per block one forward FFT
// per input channel, every channel's spectra of the last P blocks times the
// filters' P partitions summed per ear (the planar multiply-add kernels the
// renderer uses, spectral_kernels.hpp), and one inverse FFT per ear. No
// latency beyond the filters' own. Order 3 at B = 128 with 1024-tap filters:
// 16 + 2 FFTs of 256 points and 16 x 2 x 8 partition products per block.
//
// Signals: in is channels() x block() planar (channel c at [c B, (c+1) B)),
// left and right block() samples each, overwritten.
//
// A DSP unit: everything is allocated at construction; process() never
// allocates, locks or does I/O. The filters are shared read-only, so
// decoders of one design may run on any number of threads.
#pragma once

#include <complex>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "earshot/audio/aligned_vector.hpp"
#include "earshot/audio/ambisonics/binaural_decoder_design.hpp"
#include "earshot/audio/real_fft.hpp"

namespace earshot::ambisonics {

class BinauralDecoder {
 public:
  BinauralDecoder(const DecoderFilters& filters, std::size_t block);

  [[nodiscard]] int order() const { return order_; }
  [[nodiscard]] std::size_t channels() const { return channels_; }
  [[nodiscard]] std::size_t block() const { return block_; }
  [[nodiscard]] std::size_t partitions() const { return parts_; }

  void process(std::span<const float> in, std::span<float> left, std::span<float> right);
  /// Forgets every input (the filters' tails included).
  void reset();

 private:
  int order_;
  std::size_t channels_, block_, parts_, stride_;
  audio::RealFft fft_;
  audio::AlignedVector<float> filters_;  // [ear][channel][partition][re, im][stride]
  audio::AlignedVector<float> history_;  // [channel][slot][re, im][stride]: the last parts_ input spectra
  audio::AlignedVector<float> window_;   // [channel][2B]: previous and current input block
  audio::AlignedVector<float> acc_;      // [re, im][stride]
  audio::AlignedVector<std::complex<float>> spectrum_;
  audio::AlignedVector<float> time_;
  std::size_t now_ = 0;  // history slot of this block
};

}  // namespace earshot::ambisonics
