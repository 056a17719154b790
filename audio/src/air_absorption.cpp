#include "earshot/audio/air_absorption.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace earshot::audio {

AirAbsorption::AirAbsorption(double sample_rate) {
  // Butterworth low-pass by the bilinear transform (Q = 1/sqrt 2).
  const double w = 2.0 * std::numbers::pi * std::min(kReferenceHz, 0.45 * sample_rate) / sample_rate;
  const double alpha = std::sin(w) / std::numbers::sqrt2, c = std::cos(w), a0 = 1.0 + alpha;
  b0_ = (1.0 - c) / 2.0 / a0;
  b1_ = (1.0 - c) / a0;
  b2_ = b0_;
  a1_ = -2.0 * c / a0;
  a2_ = (1.0 - alpha) / a0;
}

void AirAbsorption::update(double distance_m, double factor) {
  const double d = std::isfinite(distance_m) ? std::max(0.0, distance_m) : 0.0;
  const double f = std::isfinite(factor) ? std::clamp(factor, 0.0, 10.0) : 0.0;
  target_ = std::pow(kGainPerMetre, d * f);
}

void AirAbsorption::reset() {
  z1_ = z2_ = 0.0;
  gain_ = -1.0;
  primed_ = false;
}

void AirAbsorption::process(std::span<float> block) {
  if (block.empty()) return;
  const double start = gain_ < 0.0 ? target_ : gain_;
  gain_ = target_;
  if (start == 1.0 && target_ == 1.0) {  // no absorption: leave the block as it is
    primed_ = false;
    return;
  }
  if (!primed_) {
    // Leaving the bypass (or starting): take the filter's steady state for
    // the first sample held as DC, so the low band starts where it would
    // have been rather than from zero (unity DC gain: low = x).
    const double x0 = block[0];
    z1_ = x0 * (1.0 - b0_);
    z2_ = x0 * (b2_ - a2_);
    primed_ = true;
  }
  const double step = (target_ - start) / static_cast<double>(block.size());
  for (std::size_t i = 0; i < block.size(); ++i) {
    const double x = block[i];
    const double low = b0_ * x + z1_;
    z1_ = b1_ * x - a1_ * low + z2_;
    z2_ = b2_ * x - a2_ * low;
    const double g = start + step * static_cast<double>(i + 1);
    block[i] = static_cast<float>(low + g * (x - low));
  }
}

}  // namespace earshot::audio
