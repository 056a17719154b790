// The absorption of one recirculating delay (an FDN line, a comb): a gain and
// a 4th-order high shelf, designed so that the loop loses 60 dB per t60 at
// mid frequencies and per t60 * hf_ratio at f_hf (Jot & Chaigne 1991).
//
// The shelf's corner is f_hf / 2.2: flat within 0.1 dB below 1.4 kHz, so the
// 500 Hz and 1 kHz bands decay at t60. The shelf also delays the loop (its
// group delay, a fraction of a millisecond): the gains are computed for the
// loop's true length at each frequency, or short loops would ring ~4% long.
#pragma once

#include <array>

#include "earshot/audio/biquad.hpp"

namespace earshot::audio {

struct DecayFilter {
  double gain = 1.0;
  std::array<BiquadCoeffs, 2> shelf{};
};

/// loop_samples: the delay's length; t60 (s) > 0; hf_ratio > 0; f_hf < fs / 2.
[[nodiscard]] DecayFilter design_decay_filter(double loop_samples, double t60, double hf_ratio, double f_hf,
                                              double fs);

}  // namespace earshot::audio
