// Late reverb after Schroeder (1962), with damping in the combs' loops as
// Moorer (1979) proposed: mono in, stereo out.
//
//   in -> 8 parallel feedback combs (24-37 ms at density 1), each with a
//   damping filter in its loop -> per ear, a sum with orthogonal signs,
//   then 4 series allpasses with different lengths (decorrelated stereo).
//
// Each comb's gain gives 60 dB per decay_time_s; its damping is the FDN's
// 4th-order high shelf (decay_filter.hpp), so that the loop loses 60 dB per
// decay_time_s * decay_hf_ratio at hf_reference_hz while 500 Hz and 1 kHz
// keep decay_time_s (Moorer's one-pole low-pass also shortens 1 kHz, by 75%
// in the living room, and cannot lengthen the high decay). The tail's
// energy is about late_reverb_gain^2 times the input's (with a flat decay).
// Allocates at construction only; update() and process() never allocate.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "earshot/audio/biquad.hpp"
#include "earshot/audio/room_presets.hpp"

namespace earshot::audio {

class ReverbSchroeder {
 public:
  static constexpr std::size_t kCombs = 8;
  static constexpr std::size_t kAllpasses = 4;  ///< per ear

  ReverbSchroeder(double sample_rate, std::size_t block);

  /// Takes decay_time_s, decay_hf_ratio, hf_reference_hz, density, diffusion
  /// and late_reverb_gain. A change applies from the next process().
  void update(const RoomParams& p);
  /// Writes the reverb of `in` to out_left / out_right (same length as in).
  void process(std::span<const float> in, std::span<float> out_left, std::span<float> out_right);
  void reset();

  /// The shortest comb, in seconds: the first echoes come this long after the input.
  [[nodiscard]] double latency_s() const;

 private:
  struct Allpass {
    std::size_t offset = 0, length = 0;
  };
  double rate_;
  std::vector<float> combs_;  // kCombs rings of comb_stride_ samples
  std::size_t comb_stride_ = 0, comb_mask_ = 0;
  std::array<std::size_t, kCombs> comb_len_{};
  struct Section {
    float b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0;
    Section& operator=(const BiquadCoeffs& c) {
      b0 = float(c.b0), b1 = float(c.b1), b2 = float(c.b2), a1 = float(c.a1), a2 = float(c.a2);
      return *this;
    }
  };
  std::array<float, kCombs> feedback_{};
  std::array<Section, kCombs> damp_[2]{};
  std::array<float, kCombs> z1_[2]{}, z2_[2]{};
  std::vector<float> allpass_;  // 2 * kAllpasses rings of ap_stride_ samples
  std::size_t ap_stride_ = 0, ap_mask_ = 0;
  std::array<std::size_t, 2 * kAllpasses> ap_len_{};
  float ap_g_ = 0.7f;
  float out_gain_ = 1.0f;
  std::size_t write_ = 0;
};

}  // namespace earshot::audio
