#include <algorithm>
#include <cmath>

#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

HornSynth::HornSynth(const HornParams& p, double rate) : p_(p), rate_(rate) {}

void HornSynth::generate(std::span<float> out) {
  for (float& y : out) {
    const double t = static_cast<double>(n_++) / rate_ - p_.start_s;
    double env = 0.0;
    if (t >= 0.0 && (p_.count <= 0.0 || t < p_.count * p_.period_s)) {
      const double in = std::fmod(t, p_.period_s);
      // 10 ms attack, 30 ms release: a horn starts and stops at once.
      env = std::clamp(std::min(in / 0.01, (p_.on_s - in) / 0.03), 0.0, 1.0);
    }
    // Two tones a major third apart, as car horns pair them.
    const double a = a_.next(p_.frequency_hz, rate_), b = b_.next(p_.frequency_hz * 1.26, rate_);
    y = static_cast<float>(env * 0.3 * (std::tanh(4.0 * a) + std::tanh(4.0 * b)));
  }
}

}  // namespace earshot::scenes
