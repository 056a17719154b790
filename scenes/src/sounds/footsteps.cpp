#include <algorithm>
#include <cmath>

#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

FootstepsSynth::FootstepsSynth(const FootstepsParams& p, std::uint64_t seed, double rate)
    : p_(p), rate_(rate), rng_(seed) {
  scuff_.tune(1800.0, 1500.0, rate);
  len_ = rate_ / p_.steps_per_s;
}

void FootstepsSynth::generate(std::span<float> out) {
  for (float& y : out) {
    const double t = pos_ / rate_;  // seconds into this step
    // Heel: a low thump and a scuff; toe 80 ms later, lighter.
    const double heel = std::exp(-t / 0.025), toe = t > 0.08 ? 0.5 * std::exp(-(t - 0.08) / 0.02) : 0.0;
    const double thump = thump_.next(70.0, rate_) * std::exp(-t / 0.04);
    const double scuff = scuff_.process(rng_.bipolar()) * (heel + toe);
    y = static_cast<float>(std::clamp(amp_ * (0.5 * thump + 0.9 * scuff), -1.0, 1.0));
    if (++pos_ >= len_) {
      pos_ = 0.0;
      len_ = rate_ / p_.steps_per_s * rng_.uniform(0.92, 1.08);
      amp_ = rng_.uniform(0.7, 1.0);
    }
  }
}

}  // namespace earshot::scenes
