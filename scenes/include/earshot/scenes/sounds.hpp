// Synthesised sounds for scenes: seeded, deterministic (the same parameters
// and seed give the same samples on every platform), no files, no downloads.
// Each is a small generator class; construction takes the parameters and the
// sample rate, generate() writes the next samples and never allocates.
// Output stays within [-1, 1] (SignalSource clamps as a last guard).
//
// Scene JSON signal types and their fields (defaults in brackets):
//   voice     singing on vowels: pitch_hz [220] (the tonic), melody [0,2,4,5,7,5,4,2]
//             (semitones above pitch_hz, one per note, repeated), note_s [0.5],
//             vowels ["aeiou"] (one letter per note, cycled), vibrato_hz [5.5],
//             vibrato_cents [40], formant_shift [1] (>1: a smaller vocal tract)
//   talk      speech-like babble: seed [1], pitch_hz [120] (the talker's voice),
//             syllables_per_s [4], formant_shift [1]; syllables with consonant
//             onsets, random vowels, an accent and a falling pitch per phrase,
//             pauses between phrases. Two talkers differ by pitch_hz, seed and
//             formant_shift.
//   siren     mode "wail" [default] (slow rise and fall) or "yelp" (fast upward
//             sweeps), low_hz [650], high_hz [1500], period_s [4 wail, 0.3 yelp]
//   birds     seed [1], chirps_per_s [3], pitch_hz [4000] (typical chirp pitch)
//   engine    seed [1], rpm [2400], cylinders [4]: a four-stroke's firing
//             frequency rpm/60 * cylinders/2 (80 Hz) and its harmonics, with
//             combustion noise and a slight wander
//   horn      frequency_hz [420] (a second tone a major third above),
//             on_s [0.5] (each honk), period_s [3] (honk to honk), start_s [0],
//             count [0] (honks in all; 0: for ever)
//   footsteps seed [1], steps_per_s [1.8]
//   ambience  kind "city" [default] (low pink rumble, a mains hum, distant swells)
//             or "pink" (pink noise), seed [1], hum_hz [50]
//   animal    kind "lion" | "elephant" | "monkey" | "parrot" (required), seed [1],
//             interval_s [lion 6, elephant 9, monkey 3, parrot 2.5] (mean gap
//             between calls), pitch_scale [1]
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "earshot/scenes/synth_dsp.hpp"

namespace earshot::scenes {

struct VoiceParams {
  double pitch_hz = 220.0;
  std::vector<double> melody{0, 2, 4, 5, 7, 5, 4, 2};
  double note_s = 0.5;
  std::string vowels = "aeiou";
  double vibrato_hz = 5.5;
  double vibrato_cents = 40.0;
  double formant_shift = 1.0;
};

struct TalkParams {
  double pitch_hz = 120.0;
  double syllables_per_s = 4.0;
  double formant_shift = 1.0;
};

struct SirenParams {
  enum class Mode { wail, yelp } mode = Mode::wail;
  double low_hz = 650.0, high_hz = 1500.0;
  double period_s = 0.0;  ///< 0: the mode's default (4 s wail, 0.3 s yelp)
};

struct BirdsParams {
  double chirps_per_s = 3.0;
  double pitch_hz = 4000.0;
};

struct EngineParams {
  double rpm = 2400.0;
  double cylinders = 4.0;
};

struct HornParams {
  double frequency_hz = 420.0;
  double on_s = 0.5, period_s = 3.0, start_s = 0.0;
  double count = 0.0;  ///< honks in all; 0: no end
};

struct FootstepsParams {
  double steps_per_s = 1.8;
};

struct AmbienceParams {
  enum class Kind { city, pink } kind = Kind::city;
  double hum_hz = 50.0;
};

struct AnimalParams {
  enum class Kind { lion, elephant, monkey, parrot } kind = Kind::lion;
  double interval_s = 0.0;  ///< 0: the kind's default
  double pitch_scale = 1.0;
};

/// Singing: a melody on vowels with vibrato and legato glides.
class VoiceSynth {
 public:
  VoiceSynth(const VoiceParams& p, double rate);
  void generate(std::span<float> out);

 private:
  VoiceParams p_;
  double rate_;
  std::uint64_t n_ = 0;
  double f0_ = 0.0;
  synth::Saw saw_;
  synth::OnePole tilt_;
  synth::FormantFilter formants_;
  synth::Sine vib_;
};

/// Speech-like talk: syllables in phrases, a distinct voice per talker.
class TalkSynth {
 public:
  TalkSynth(const TalkParams& p, std::uint64_t seed, double rate);
  void generate(std::span<float> out);

 private:
  void next_syllable();
  TalkParams p_;
  double rate_;
  synth::Rng rng_;
  synth::Saw saw_;
  synth::OnePole tilt_;
  synth::FormantFilter formants_;
  synth::Resonator fricative_;
  double pos_ = 0, len_ = 0, gap_ = 0;  // samples into, of, and after the syllable
  double pitch_ = 0, f0_ = 0, consonant_ = 0, loud_ = 1;
  int left_in_phrase_ = 0, phrase_len_ = 1;
};

/// Emergency-vehicle siren: wail or yelp, a bright square-ish tone.
class SirenSynth {
 public:
  SirenSynth(const SirenParams& p, double rate);
  void generate(std::span<float> out);

 private:
  SirenParams p_;
  double rate_;
  std::uint64_t n_ = 0;
  synth::Sine osc_;
};

/// Bird chirps: quick frequency sweeps in little trills at random times.
class BirdsSynth {
 public:
  BirdsSynth(const BirdsParams& p, std::uint64_t seed, double rate);
  void generate(std::span<float> out);

 private:
  void next_chirp();
  BirdsParams p_;
  double rate_;
  synth::Rng rng_;
  synth::Sine osc_;
  double pos_ = 0, len_ = 1, wait_ = 0, f_start_ = 0, f_end_ = 0, amp_ = 0;
  int notes_left_ = 0;
};

/// Engine: harmonic rumble at the firing frequency, with combustion noise.
class EngineSynth {
 public:
  EngineSynth(const EngineParams& p, std::uint64_t seed, double rate);
  void generate(std::span<float> out);
  /// The firing frequency (Hz) the engine runs at on average.
  [[nodiscard]] double firing_hz() const { return p_.rpm / 60.0 * p_.cylinders / 2.0; }

 private:
  EngineParams p_;
  double rate_;
  synth::Rng rng_;
  double phase_ = 0, wander_ = 0;
  synth::OnePole noise_lp_, wander_lp_;
};

/// Car horn: two detuned square-ish tones, honking on a fixed pattern.
class HornSynth {
 public:
  HornSynth(const HornParams& p, double rate);
  void generate(std::span<float> out);

 private:
  HornParams p_;
  double rate_;
  std::uint64_t n_ = 0;
  synth::Sine a_, b_;
};

/// Footsteps: heel thump and scuff, then a lighter toe, at a walking pace.
class FootstepsSynth {
 public:
  FootstepsSynth(const FootstepsParams& p, std::uint64_t seed, double rate);
  void generate(std::span<float> out);

 private:
  FootstepsParams p_;
  double rate_;
  synth::Rng rng_;
  synth::Resonator scuff_;
  synth::Sine thump_;
  double pos_ = 0, len_ = 1, amp_ = 1;
};

/// Background ambience: city (rumble, hum, swells) or pink noise.
class AmbienceSynth {
 public:
  AmbienceSynth(const AmbienceParams& p, std::uint64_t seed, double rate);
  void generate(std::span<float> out);

 private:
  AmbienceParams p_;
  double rate_;
  synth::PinkNoise pink_;
  synth::OnePole rumble_, swell_;
  synth::Rng rng_;
  synth::Sine hum_[3];
  double swell_target_ = 0.5;
  std::uint64_t n_ = 0;
};

/// Zoo animals: lion roar, elephant trumpet, monkey chatter, parrot squawk.
class AnimalSynth {
 public:
  AnimalSynth(const AnimalParams& p, std::uint64_t seed, double rate);
  void generate(std::span<float> out);

 private:
  void next_call();
  double sample();
  AnimalParams p_;
  double rate_;
  synth::Rng rng_;
  synth::Saw saw_;
  synth::Sine sine_, am_;
  synth::FormantFilter formants_;
  synth::OnePole noise_lp_;
  double pos_ = 0, len_ = 0, wait_ = 0, pitch_ = 0, amp_ = 1;
  int notes_left_ = 0;  // monkey chatter: notes left in this bout
};

}  // namespace earshot::scenes
