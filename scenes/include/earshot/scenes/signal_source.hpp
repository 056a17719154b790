// Mono signal generators for scene sources, deterministic for a seed.
// Builtins: noise (white, uniform in [-1, 1)), sine, impulse; file signals
// are read whole at construction (libsndfile: WAV, FLAC, OGG, ...), mixed to
// mono (the channels' mean) and resampled to the scene's rate with
// libsamplerate; the synthesised sounds are in sounds.hpp.
// generate() never allocates and its samples stay within [-1, 1].
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <variant>
#include <vector>

#include "earshot/scenes/scene.hpp"
#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

class SignalSource {
 public:
  /// Throws earshot::InputError naming the file when a file signal's file is
  /// missing, unreadable, empty or cannot be resampled.
  SignalSource(const Signal& s, double sample_rate);
  /// The next samples of the signal.
  void generate(std::span<float> out);

 private:
  using Synth = std::variant<std::monostate, VoiceSynth, TalkSynth, SirenSynth, BirdsSynth, EngineSynth, HornSynth,
                             FootstepsSynth, AmbienceSynth, AnimalSynth>;
  Signal sig_;
  double rate_;
  std::uint64_t n_ = 0;
  std::mt19937_64 rng_;
  std::vector<float> file_;
  Synth synth_;
};

}  // namespace earshot::scenes
