// A delay line read at a fractional, moving delay: the ITD and propagation
// delay of one source and ear. The delay glides linearly from the previous
// block's value to the new one across each block (a smoothed change: no
// click, and a changing delay bends the pitch as Doppler does).
//
// Reads are band-limited: a 16-tap Kaiser-windowed sinc for the delay's
// fraction. The fraction range is cut into 32 cells, and within a cell each
// tap is a quadratic in the place in the cell, through the exact kernels at
// its start, middle and end: within 106 dB of the exact response up to
// 20 kHz, exact at whole delays, continuous from cell to cell. Its response
// is flat to within 0.1 dB up to 16 kHz at 48 kHz for every fraction, so a
// fractional delay never low-passes one ear more than the other (a cubic
// Lagrange read did, which shrank the rendered ILD by up to 0.4 dB). The
// kernel reaches eight samples ahead: the delay is never less than kMinDelay
// samples (a fixed latency callers add).
//
// A read whose delay does not move across the block runs as one fixed FIR
// (vectorised across samples). A gliding read runs the chosen instruction
// set's kernel (simd_kernels.hpp). The AVX2 one takes eight or sixteen
// samples at a time: their kernels mostly share a cell, so the three
// coefficient FIRs run across those samples together and the quadratic
// combines them per sample; groups of eight that span more than three cells
// (a fast Doppler glide), and the portable kernel, compute one kernel per
// sample. Allocates at construction only.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "earshot/audio/simd_kernels.hpp"

namespace earshot::audio {

class FractionalDelay {
 public:
  static constexpr double kMinDelay = 8.0;
  static constexpr std::size_t kTaps = 16;
  static constexpr std::size_t kCells = 32;  // kernel cells per sample of fraction, a power of two

  /// `isa_kernels` runs the gliding read (tests pass each instruction set's
  /// to compare them; the default is the one chosen for this process).
  FractionalDelay(std::size_t block, double max_delay_samples,
                  const simd::Kernels& isa_kernels = simd::kernels());

  /// Writes `in` and reads `out` (both block samples) at a delay moving to
  /// `delay_samples` (clamped to [kMinDelay, max]). The first call starts there.
  void process(std::span<const float> in, std::span<float> out, double delay_samples);

  /// The same in two steps, for several reads of one signal (a source's two
  /// ears): write() appends a block, read() reads that block (out.size()
  /// samples, as many as were written) at a delay gliding from `from` to
  /// `to` samples, each clamped to [kMinDelay, max]; a NaN reads kMinDelay.
  void write(std::span<const float> in);
  void read(std::span<float> out, double from, double to) const;
  [[nodiscard]] double clamp_delay(double delay_samples) const {
    return std::clamp(std::isfinite(delay_samples) ? delay_samples : kMinDelay, kMinDelay, max_delay_);
  }
  /// Asks the CPU for the ring lines that the next block's write (n
  /// samples) and reads (at delays near `shortest` to `longest`) will need,
  /// before write(): with many delay lines these were last touched blocks
  /// ago and have left the nearer caches. A hint only: changes no state.
  void prefetch(std::size_t n, double shortest, double longest) const;
  void reset();
  [[nodiscard]] double max_delay() const { return max_delay_; }

 private:
  std::vector<float> ring_;  // size_ samples plus a mirror of the first kTaps + 16
  std::size_t size_;
  std::size_t write_ = 0;
  double max_delay_;
  double delay_ = -1.0;  // previous block's delay; < 0 before the first block
  const float* kernels_;  // kCells cells of three coefficient rows, shared and immutable
  const simd::Kernels* simd_;  // the gliding read's instruction set (chosen once, not per block)
};

}  // namespace earshot::audio
