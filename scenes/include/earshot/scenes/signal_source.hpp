// Mono signal generators for scene sources, deterministic for a seed.
// Files are read whole at construction (libsndfile); generate() never allocates.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "earshot/scenes/scene.hpp"

namespace earshot::scenes {

class SignalSource {
 public:
  /// Throws earshot::InputError for an unreadable file or one at another rate.
  SignalSource(const Signal& s, double sample_rate);
  /// The next samples of the signal.
  void generate(std::span<float> out);

 private:
  Signal sig_;
  double rate_;
  std::uint64_t n_ = 0;
  std::mt19937_64 rng_;
  std::vector<float> file_;
};

}  // namespace earshot::scenes
