#include <algorithm>
#include <cmath>

#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

AmbienceSynth::AmbienceSynth(const AmbienceParams& p, std::uint64_t seed, double rate)
    : p_(p), rate_(rate), pink_(seed, rate), rng_(seed ^ 0x9e3779b97f4a7c15ULL) {
  rumble_.cutoff(700.0, rate);
  swell_.cutoff(0.15, rate);
}

void AmbienceSynth::generate(std::span<float> out) {
  for (float& y : out) {
    const double pink = pink_.next();
    if (p_.kind == AmbienceParams::Kind::pink) {
      y = static_cast<float>(std::clamp(0.25 * pink, -1.0, 1.0));
      continue;
    }
    // City: distant traffic (pink noise below 700 Hz) that swells and ebbs
    // every few seconds, and a faint mains hum with two harmonics.
    if (n_++ % static_cast<std::uint64_t>(rate_ * 2.0) == 0) swell_target_ = rng_.uniform(0.3, 1.0);
    const double swell = swell_.process(swell_target_);
    const double hum = hum_[0].next(p_.hum_hz, rate_) + 0.5 * hum_[1].next(2.0 * p_.hum_hz, rate_) +
                       0.25 * hum_[2].next(3.0 * p_.hum_hz, rate_);
    y = static_cast<float>(std::clamp(0.5 * swell * rumble_.process(pink) + 0.02 * hum, -1.0, 1.0));
  }
}

}  // namespace earshot::scenes
