#include <algorithm>
#include <cmath>

#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {
namespace {
using Kind = AnimalParams::Kind;
double default_interval(Kind k) {
  switch (k) {
    case Kind::lion: return 6.0;
    case Kind::elephant: return 9.0;
    case Kind::monkey: return 3.0;
    case Kind::parrot: return 2.5;
  }
  return 5.0;
}
}  // namespace

AnimalSynth::AnimalSynth(const AnimalParams& p, std::uint64_t seed, double rate) : p_(p), rate_(rate), rng_(seed) {
  if (p_.interval_s <= 0.0) p_.interval_s = default_interval(p_.kind);
  noise_lp_.cutoff(p_.kind == Kind::parrot ? 3000.0 : 400.0, rate);
  next_call();
  wait_ = rng_.uniform(0.1, 0.6) * p_.interval_s * rate_;  // animals do not call on cue
}

void AnimalSynth::next_call() {
  pos_ = 0.0;
  const double s = p_.pitch_scale;
  switch (p_.kind) {
    case Kind::lion:  // a long, low, rough "aaoo" that falls
      len_ = rng_.uniform(1.2, 2.0) * rate_;
      pitch_ = rng_.uniform(110, 150) * s;
      formants_.jump({450 * s, 800 * s, 2300 * s});
      break;
    case Kind::elephant:  // a loud brassy trumpet, rising
      len_ = rng_.uniform(0.9, 1.5) * rate_;
      pitch_ = rng_.uniform(380, 480) * s;
      formants_.jump({900 * s, 1700 * s, 2900 * s});
      break;
    case Kind::monkey:  // bouts of short "ee-ee-ee" calls
      if (notes_left_ <= 0) notes_left_ = 4 + static_cast<int>(rng_.uniform() * 8.0);
      len_ = rng_.uniform(0.06, 0.11) * rate_;
      pitch_ = rng_.uniform(700, 1300) * s;
      formants_.jump({700 * s, 2300 * s, 3200 * s});
      break;
    case Kind::parrot:  // a harsh squawk
      len_ = rng_.uniform(0.15, 0.35) * rate_;
      pitch_ = rng_.uniform(1400, 2400) * s;
      formants_.jump({1800 * s, 3200 * s, 4500 * s});
      break;
  }
  amp_ = rng_.uniform(0.75, 1.0);
  if (p_.kind == Kind::monkey && --notes_left_ > 0)
    wait_ += rng_.uniform(0.03, 0.08) * rate_;
  else
    wait_ += p_.interval_s * rng_.uniform(0.5, 1.5) * rate_;
}

double AnimalSynth::sample() {
  const double f = pos_ / len_;
  const double noise = rng_.bipolar();
  switch (p_.kind) {
    case Kind::lion: {
      // Pitch falls through the roar; a 25 Hz flutter and breath noise make it rough.
      const double env = synth::event_envelope(pos_, len_, 0.35 * len_);
      const double pitch = pitch_ * (1.1 - 0.45 * f);
      const double rough = 0.6 + 0.4 * am_.next(25.0, rate_);
      const double src = saw_.next(pitch, rate_) * rough + 1.5 * noise_lp_.process(noise);
      return 0.8 * env * formants_.process(src, rate_);
    }
    case Kind::elephant: {
      const double env = std::min(1.0, f / 0.1) * std::min(1.0, (1.0 - f) / 0.2);
      const double pitch = pitch_ * (1.0 + 0.15 * std::min(1.0, f * 3.0)) * (1.0 + 0.01 * noise);
      const double src = std::tanh(2.5 * saw_.next(pitch, rate_)) + 0.2 * noise;
      return 0.9 * env * formants_.process(src, rate_);
    }
    case Kind::monkey: {
      const double env = std::sin(std::numbers::pi * f);
      const double pitch = pitch_ * (1.0 + 0.4 * f);  // each "ee" slides up
      return 0.9 * env * formants_.process(saw_.next(pitch, rate_), rate_);
    }
    case Kind::parrot: {
      const double env = std::sin(std::numbers::pi * f);
      const double pitch = pitch_ * (1.0 + 0.2 * sine_.next(35.0, rate_));
      const double src = saw_.next(pitch, rate_) * (0.5 + 0.5 * am_.next(120.0, rate_)) + noise_lp_.process(noise);
      return 0.8 * env * formants_.process(src, rate_);
    }
  }
  return 0.0;
}

void AnimalSynth::generate(std::span<float> out) {
  for (float& y : out) {
    if (wait_ > 0.0) {
      wait_ -= 1.0;
      y = static_cast<float>(std::clamp(0.5 * formants_.process(0.0, rate_), -1.0, 1.0));
      continue;
    }
    y = static_cast<float>(std::clamp(amp_ * sample(), -1.0, 1.0));
    if (++pos_ >= len_) next_call();
  }
}

}  // namespace earshot::scenes
