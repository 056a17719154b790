// Late reverb: a feedback delay network (Jot & Chaigne 1991), mono in,
// stereo out.
//
//   in -> 4 series allpasses (diffusion) -> b (signs) -> 16 delay lines
//   each line: gain and 4th-order high shelf (decay_filter.hpp), so that the
//   line loses 60 dB per decay_time_s at mid frequencies (500 Hz and 1 kHz)
//   and per decay_time_s * decay_hf_ratio at hf_reference_hz; feedback through a 16 x 16 Hadamard matrix (orthogonal,
//   every line feeds every line equally: fast echo build-up).
//   left and right: two other Hadamard rows over the line outputs, which are
//   orthogonal, so the ears are decorrelated.
//
// Line lengths are 11-37 ms at density 1 (mutually prime), shorter for less
// dense rooms. The output is scaled so that the tail's energy is about
// late_reverb_gain^2 times the input's (Table 1: 0 dB ~ the input's energy) with a
// flat decay; a shorter high-frequency decay leaves less.
// Allocates at construction only; update() and process() never allocate.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "earshot/audio/room_presets.hpp"

namespace earshot::audio {

class ReverbFdn {
 public:
  static constexpr std::size_t kLines = 16;
  static constexpr std::size_t kDiffusers = 4;

  ReverbFdn(double sample_rate, std::size_t block);

  /// Takes decay_time_s, decay_hf_ratio, hf_reference_hz, density, diffusion
  /// and late_reverb_gain. A change applies from the next process().
  void update(const RoomParams& p);
  /// Writes the reverb of `in` to out_left / out_right (same length as in).
  void process(std::span<const float> in, std::span<float> out_left, std::span<float> out_right);
  void reset();

  /// The shortest line, in seconds: the first echoes come this long after the input.
  [[nodiscard]] double latency_s() const;

 private:
  double rate_;
  std::size_t stride_ = 0, mask_ = 0, write_ = 0;
  std::vector<float> lines_;  // kLines rings of stride_ samples, one after another
  std::array<std::size_t, kLines> length_{};
  // Per line: gain and the shelf's two sections, structure of arrays so the
  // compiler can run the 16 lines side by side.
  alignas(32) std::array<float, kLines> gain_{};
  alignas(32) std::array<float, kLines> b0_[2]{}, b1_[2]{}, b2_[2]{}, a1_[2]{}, a2_[2]{};
  alignas(32) std::array<float, kLines> z1_[2]{}, z2_[2]{};
  // Input diffusion allpasses.
  std::vector<float> diff_buf_;
  std::size_t diff_stride_ = 0, diff_mask_ = 0;
  std::array<std::size_t, kDiffusers> diff_len_{};
  float diff_g_ = 0.6f;
  float out_gain_ = 1.0f;
};

}  // namespace earshot::audio
