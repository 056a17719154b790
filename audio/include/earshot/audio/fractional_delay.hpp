// A delay line read at a fractional, moving delay: the ITD and propagation
// delay of one source and ear. The delay glides linearly from the previous
// block's value to the new one across each block (a smoothed change: no
// click, and a changing delay bends the pitch as Doppler does). Reads use
// 4-point Lagrange (cubic) interpolation, which needs two samples ahead: the
// delay is never less than kMinDelay samples (a fixed latency callers add).
// Allocates at construction only.
#pragma once

#include <span>
#include <vector>

namespace earshot::audio {

class FractionalDelay {
 public:
  static constexpr double kMinDelay = 2.0;

  FractionalDelay(std::size_t block, double max_delay_samples);

  /// Writes `in` and reads `out` (both block samples) at a delay moving to
  /// `delay_samples` (clamped to [kMinDelay, max]). The first call starts there.
  void process(std::span<const float> in, std::span<float> out, double delay_samples);
  void reset();
  [[nodiscard]] double max_delay() const { return max_delay_; }

 private:
  std::vector<float> ring_;
  std::size_t mask_;
  std::size_t write_ = 0;
  double max_delay_;
  double delay_ = -1.0;  // previous block's delay; < 0 before the first block
};

}  // namespace earshot::audio
