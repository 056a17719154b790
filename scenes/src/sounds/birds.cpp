#include <algorithm>
#include <cmath>

#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

BirdsSynth::BirdsSynth(const BirdsParams& p, std::uint64_t seed, double rate) : p_(p), rate_(rate), rng_(seed) {
  wait_ = rng_.uniform(0.0, 0.5) * rate_;
  next_chirp();
}

void BirdsSynth::next_chirp() {
  if (notes_left_ <= 0) {  // a new trill after a random pause (mean 1 / chirps_per_s)
    notes_left_ = 1 + static_cast<int>(rng_.uniform() * 5.0);
    wait_ += -std::log(1.0 - rng_.uniform()) / p_.chirps_per_s * rate_;
  } else {
    wait_ += rng_.uniform(0.02, 0.06) * rate_;
  }
  --notes_left_;
  len_ = rng_.uniform(0.04, 0.14) * rate_;
  pos_ = 0.0;
  const double centre = p_.pitch_hz * rng_.uniform(0.8, 1.25);
  const bool down = rng_.chance(0.6);
  f_start_ = centre * (down ? 1.3 : 0.75);
  f_end_ = centre * (down ? 0.8 : 1.25);
  amp_ = rng_.uniform(0.4, 0.8);
}

void BirdsSynth::generate(std::span<float> out) {
  for (float& y : out) {
    if (wait_ > 0.0) {
      wait_ -= 1.0;
      y = 0.0f;
      continue;
    }
    const double f = pos_ / len_;
    const double env = std::sin(std::numbers::pi * f);
    const double s = osc_.next(f_start_ + (f_end_ - f_start_) * f, rate_);
    y = static_cast<float>(std::clamp(amp_ * env * env * (s + 0.15 * s * s), -1.0, 1.0));
    if (++pos_ >= len_) next_chirp();
  }
}

}  // namespace earshot::scenes
