// Band-limited resampling of impulse responses, for HRIR sets measured at
// another rate than the render rate (MIT KEMAR is 44.1 kHz, a render 48 kHz).
//
// Every response of a set has the same length, so every output sample sits
// at the same place between input samples in all of them: the kernel of
// each output sample is computed once (a Kaiser-windowed sinc, cut off at
// 95% of the lower rate's Nyquist frequency, 32 taps of the lower rate each
// side, shape 9: stopband near -90 dB) and applied to every response. The
// output is zero-phase (no latency: an onset stays where it was in time) and
// as long as ceil(length * to / from), as libmysofa's resampler makes it.
// Delays stored beside the responses (SOFA's Data.Delay) are the caller's to
// rescale.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace earshot::hrtf {

class IrResampler {
 public:
  /// Rates in Hz (> 0); `in_length` samples per response.
  IrResampler(double from_hz, double to_hz, std::size_t in_length);

  [[nodiscard]] std::size_t in_length() const { return in_length_; }
  [[nodiscard]] std::size_t out_length() const { return first_.size(); }
  /// What out_length() will be, without building the kernels (callers
  /// bound it first: the kernels take time and memory in proportion).
  [[nodiscard]] static std::size_t out_length_for(double from_hz, double to_hz, std::size_t in_length);

  /// Resamples one response: `in` holds in_length() samples, `out`
  /// out_length(). Does not allocate.
  void process(std::span<const float> in, std::span<float> out) const;

 private:
  std::size_t in_length_;
  std::size_t taps_;                 // kernel length
  std::vector<std::int64_t> first_;  // [output sample]: the input index of its first tap
  std::vector<float> weights_;       // [output sample][tap]
};

}  // namespace earshot::hrtf
