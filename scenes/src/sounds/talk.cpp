#include <algorithm>
#include <cmath>

#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

TalkSynth::TalkSynth(const TalkParams& p, std::uint64_t seed, double rate) : p_(p), rate_(rate), rng_(seed) {
  tilt_.cutoff(1500.0, rate);
  fricative_.tune(4500.0, 2500.0, rate);
  gap_ = rng_.uniform(0.0, 0.3) * rate_;  // talkers do not all start together
  next_syllable();
}

void TalkSynth::next_syllable() {
  if (left_in_phrase_ <= 0) {  // a new phrase, after a pause
    phrase_len_ = left_in_phrase_ = 3 + static_cast<int>(rng_.uniform() * 6.0);
    gap_ += rng_.uniform(0.25, 0.7) * rate_;
  }
  const double progress = 1.0 - static_cast<double>(left_in_phrase_) / phrase_len_;
  --left_in_phrase_;
  len_ = rate_ / p_.syllables_per_s * rng_.uniform(0.6, 1.4);
  pos_ = 0.0;
  // Declination over the phrase, an accent now and then.
  pitch_ = p_.pitch_hz * (1.0 - 0.15 * progress) * (rng_.chance(0.3) ? 1.2 : rng_.uniform(0.95, 1.05));
  consonant_ = rng_.chance(0.6) ? rng_.uniform(0.12, 0.3) : 0.0;  // fraction of the syllable
  loud_ = rng_.uniform(0.7, 1.0);
  static constexpr char kVowels[] = "aeiou";
  const auto v = synth::vowel_formants(kVowels[static_cast<int>(rng_.uniform() * 5.0)]);
  formants_.target({v.f1 * p_.formant_shift, v.f2 * p_.formant_shift, v.f3 * p_.formant_shift});
}

void TalkSynth::generate(std::span<float> out) {
  const double glide = 1.0 - std::exp(-1.0 / (0.04 * rate_));
  for (float& y : out) {
    double s = 0.0;
    if (gap_ > 0.0) {
      gap_ -= 1.0;
      s = formants_.process(0.0, rate_);  // let the resonators ring out
    } else {
      const double f = pos_ / len_;
      f0_ += glide * (pitch_ * (1.0 - 0.1 * f) - f0_);
      const double noise = rng_.bipolar();
      double voiced = 0.0, fric = 0.0;
      if (f < consonant_) {
        fric = std::sin(std::numbers::pi * f / consonant_);
      } else {
        const double g = (f - consonant_) / (1.0 - consonant_);
        voiced = std::sin(std::numbers::pi * g);  // the vowel swells and fades
      }
      const double src = tilt_.process(saw_.next(std::max(f0_, 40.0), rate_) + 0.05 * noise);
      s = loud_ * (voiced * formants_.process(src, rate_) + 0.25 * fric * fricative_.process(noise));
      if (++pos_ >= len_) next_syllable();
    }
    y = static_cast<float>(std::clamp(0.45 * s, -1.0, 1.0));
  }
}

}  // namespace earshot::scenes
