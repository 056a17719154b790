// A delay line read at a fractional, moving delay: the ITD and propagation
// delay of one source and ear. The delay glides linearly from the previous
// block's value to the new one across each block (a smoothed change: no
// click, and a changing delay bends the pitch as Doppler does).
//
// Reads are band-limited: a 16-tap Kaiser-windowed sinc for the delay's
// fraction, interpolated linearly between the rows of a 128-entry table
// (16 KB, so it stays in cache; rounding to the nearest of 1024 rows left
// sidebands only ~80 dB down, loud enough to show once an HRTF boosts
// 2-4 kHz). Its response is flat to within 0.1 dB up to 16 kHz at 48 kHz
// for every fraction, so a fractional delay never low-passes one ear more
// than the other (a cubic Lagrange read did, which shrank the rendered ILD
// by up to 0.4 dB). The kernel reaches eight samples ahead: the delay is
// never less than kMinDelay samples (a fixed latency callers add). A read
// whose delay does not move across the block runs as one fixed FIR
// (vectorised across samples); a gliding read computes eight samples' dot
// products together (AVX2 where the CPU has it). Allocates at construction
// only.
#pragma once

#include <span>
#include <vector>

namespace earshot::audio {

class FractionalDelay {
 public:
  static constexpr double kMinDelay = 8.0;
  static constexpr std::size_t kTaps = 16;
  static constexpr std::size_t kPhases = 128;  // table entries, a power of two

  FractionalDelay(std::size_t block, double max_delay_samples);

  /// Writes `in` and reads `out` (both block samples) at a delay moving to
  /// `delay_samples` (clamped to [kMinDelay, max]). The first call starts there.
  void process(std::span<const float> in, std::span<float> out, double delay_samples);

  /// The same in two steps, for several reads of one signal (a source's two
  /// ears): write() appends a block, read() reads that block (out.size()
  /// samples, as many as were written) at a delay gliding from `from` to
  /// `to` samples, each clamped to [kMinDelay, max]; a NaN reads kMinDelay.
  void write(std::span<const float> in);
  void read(std::span<float> out, double from, double to) const;
  [[nodiscard]] double clamp_delay(double delay_samples) const;
  void reset();
  [[nodiscard]] double max_delay() const { return max_delay_; }

 private:
  std::vector<float> ring_;  // size_ samples plus a mirror of the first kTaps
  std::size_t size_;
  std::size_t write_ = 0;
  double max_delay_;
  double delay_ = -1.0;  // previous block's delay; < 0 before the first block
  const float* kernels_;  // kPhases entries of a row and its change, shared and immutable
  bool avx2_ = false;     // the gliding read's AVX2 path (checked once, here, not per block)
};

}  // namespace earshot::audio
