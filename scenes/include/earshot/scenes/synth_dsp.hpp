// Small building blocks of the synthesised sounds (sounds.hpp): a seeded
// random generator, a formant resonator, a glottal-like source, pink noise
// and an event clock. All allocation-free and deterministic; their state is
// a few doubles, so the generators holding them can be copied freely.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace earshot::scenes::synth {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Seeded randomness with our own mapping of the 64-bit Mersenne Twister
/// (whose sequence the standard fixes), so every platform draws the same.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : g_(seed) {}
  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(g_() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform in [-1, 1).
  double bipolar() { return 2.0 * uniform() - 1.0; }
  /// True with probability p.
  bool chance(double p) { return uniform() < p; }

 private:
  std::mt19937_64 g_;
};

/// Two-pole resonator (a formant): centre frequency and bandwidth in Hz,
/// scaled for a peak gain near one.
class Resonator {
 public:
  void tune(double freq_hz, double bandwidth_hz, double rate) {
    const double r = std::exp(-std::numbers::pi * bandwidth_hz / rate);
    const double th = kTwoPi * std::min(freq_hz, 0.45 * rate) / rate;
    a1_ = 2.0 * r * std::cos(th);
    a2_ = -r * r;
    b0_ = (1.0 - r * r) * std::sin(th) + 1e-9;
  }
  double process(double x) {
    const double y = b0_ * x + a1_ * y1_ + a2_ * y2_;
    y2_ = y1_;
    y1_ = y;
    return y;
  }

 private:
  double a1_ = 0, a2_ = 0, b0_ = 0, y1_ = 0, y2_ = 0;
};

/// One-pole low-pass: y += k (x - y).
class OnePole {
 public:
  void cutoff(double hz, double rate) { k_ = 1.0 - std::exp(-kTwoPi * hz / rate); }
  double process(double x) { return y_ += k_ * (x - y_); }

 private:
  double k_ = 1.0, y_ = 0.0;
};

/// Band-limited sawtooth (polyBLEP at the wrap): a bright, voice-like pulse
/// source whose frequency may change every sample.
class Saw {
 public:
  double next(double freq_hz, double rate) {
    const double dt = std::min(freq_hz / rate, 0.5);
    phase_ += dt;
    if (phase_ >= 1.0) phase_ -= 1.0;
    double y = 2.0 * phase_ - 1.0;
    if (phase_ < dt) {
      const double t = phase_ / dt;
      y -= t + t - t * t - 1.0;
    } else if (phase_ > 1.0 - dt) {
      const double t = (phase_ - 1.0) / dt;
      y -= t * t + t + t + 1.0;
    }
    return y;
  }
  [[nodiscard]] double phase() const { return phase_; }

 private:
  double phase_ = 0.0;
};

/// A sine oscillator whose frequency may change every sample.
class Sine {
 public:
  double next(double freq_hz, double rate) {
    phase_ += freq_hz / rate;
    phase_ -= std::floor(phase_);
    return std::sin(kTwoPi * phase_);
  }

 private:
  double phase_ = 0.0;
};

/// Pink-ish noise (-3 dB/octave within 1 dB from 40 Hz to 10 kHz at 48 kHz):
/// white noise through five one-pole low-passes an octave and a bit apart,
/// summed with weights that follow 1/sqrt(f).
class PinkNoise {
 public:
  PinkNoise(std::uint64_t seed, double rate) : rng_(seed) {
    double f = 20.0;
    for (auto& p : poles_) {
      p.cutoff(f, rate);
      f *= 5.0;
    }
  }
  double next() {
    const double w = rng_.bipolar();
    double y = 0.0, weight = 1.0;
    for (auto& p : poles_) {
      y += weight * p.process(w);
      weight *= 0.45;
    }
    return 3.0 * y;
  }

 private:
  Rng rng_;
  OnePole poles_[5];
};

/// Vowel formants (F1, F2, F3 in Hz, an adult male's; scaled for others).
struct Formants {
  double f1, f2, f3;
};
/// 'a', 'e', 'i', 'o', 'u' (anything else: a neutral schwa).
[[nodiscard]] constexpr Formants vowel_formants(char v) {
  switch (v) {
    case 'a': return {730, 1090, 2440};
    case 'e': return {530, 1840, 2480};
    case 'i': return {270, 2290, 3010};
    case 'o': return {570, 840, 2410};
    case 'u': return {300, 870, 2240};
    default: return {500, 1500, 2500};
  }
}

/// Three parallel formant resonators on a source, retuned smoothly: the
/// formants glide toward their targets (about 20 ms), like a moving tongue.
class FormantFilter {
 public:
  void target(Formants f) { target_ = f; }
  void jump(Formants f) { cur_ = target_ = f; }
  double process(double x, double rate) {
    if (count_++ % 16 == 0) {  // retune every 16 samples: smooth enough, cheap
      const double k = 1.0 - std::exp(-16.0 / (0.02 * rate));
      cur_.f1 += k * (target_.f1 - cur_.f1);
      cur_.f2 += k * (target_.f2 - cur_.f2);
      cur_.f3 += k * (target_.f3 - cur_.f3);
      r_[0].tune(cur_.f1, 80.0, rate);
      r_[1].tune(cur_.f2, 110.0, rate);
      r_[2].tune(cur_.f3, 160.0, rate);
    }
    return r_[0].process(x) + 0.6 * r_[1].process(x) + 0.3 * r_[2].process(x);
  }

 private:
  Formants cur_{500, 1500, 2500}, target_{500, 1500, 2500};
  Resonator r_[3];
  std::uint64_t count_ = 0;
};

/// Attack-decay envelope of one event of `length` samples: a raised-cosine
/// attack over `attack` samples, then an exponential-ish fall to zero.
[[nodiscard]] inline double event_envelope(double pos, double length, double attack) {
  if (pos < 0.0 || pos >= length) return 0.0;
  if (pos < attack) return 0.5 - 0.5 * std::cos(std::numbers::pi * pos / attack);
  const double f = (pos - attack) / std::max(1.0, length - attack);
  return (1.0 - f) * (1.0 - f);
}

}  // namespace earshot::scenes::synth
