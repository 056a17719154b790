#include <algorithm>
#include <cmath>

#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

EngineSynth::EngineSynth(const EngineParams& p, std::uint64_t seed, double rate) : p_(p), rate_(rate), rng_(seed) {
  noise_lp_.cutoff(600.0, rate);
  wander_lp_.cutoff(0.5, rate);
}

void EngineSynth::generate(std::span<float> out) {
  const double f0 = firing_hz();
  for (float& y : out) {
    // The rpm wanders a little (about 0.1 %), slowly: an engine, not an organ.
    wander_ = wander_lp_.process(rng_.bipolar() * 0.3);
    phase_ += f0 * (1.0 + wander_) / rate_;
    phase_ -= std::floor(phase_);
    double h = 0.0;
    for (int k = 1; k <= 8; ++k) h += std::sin(synth::kTwoPi * k * phase_) / (k * k > 1 ? 1.5 * k : 1.0);
    // Combustion noise comes in a burst after each firing.
    const double burst = std::exp(-6.0 * phase_);
    const double noise = noise_lp_.process(rng_.bipolar()) * burst;
    y = static_cast<float>(std::clamp(0.22 * h + 0.8 * noise, -1.0, 1.0));
  }
}

}  // namespace earshot::scenes
