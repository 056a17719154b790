#include <algorithm>
#include <cmath>

#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

SirenSynth::SirenSynth(const SirenParams& p, double rate) : p_(p), rate_(rate) {
  if (p_.period_s <= 0.0) p_.period_s = p_.mode == SirenParams::Mode::wail ? 4.0 : 0.3;
}

void SirenSynth::generate(std::span<float> out) {
  for (float& y : out) {
    const double c = static_cast<double>(n_++) / rate_ / p_.period_s;
    const double frac = c - std::floor(c);
    // Wail: a smooth rise and fall; yelp: a quick upward sweep, again and again.
    const double sweep = p_.mode == SirenParams::Mode::wail ? 0.5 - 0.5 * std::cos(synth::kTwoPi * frac)
                                                            : std::sqrt(frac);
    const double f = p_.low_hz + (p_.high_hz - p_.low_hz) * sweep;
    // A driven horn speaker: a sine pushed into a square-ish tone.
    y = static_cast<float>(0.45 * std::tanh(3.0 * osc_.next(f, rate_)));
  }
}

}  // namespace earshot::scenes
