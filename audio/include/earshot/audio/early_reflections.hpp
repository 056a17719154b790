// Early reflections: a tapped delay line, mono in, stereo out. The first tap
// sits at the preset's reflections delay; eight taps follow over ~20 ms
// (shorter for less dense rooms), alternately stronger left and right with
// alternating signs, so the two ears get different, uncorrelated patterns.
// The taps' energies, both ears together, add up to reflections_gain^2 (a
// unit impulse in gives out reflections_gain^2 of energy, about half in each
// ear). Allocates at construction only.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "earshot/audio/room_presets.hpp"

namespace earshot::audio {

class EarlyReflections {
 public:
  static constexpr std::size_t kTaps = 8;
  static constexpr double kMaxDelayS = 0.3 + 0.03;  ///< EFX's longest reflections delay + the tap spread

  EarlyReflections(double sample_rate, std::size_t block);

  /// Takes reflections_delay_s, reflections_gain and density; never allocates.
  void update(const RoomParams& p);
  /// Adds the reflections of `in` into out_left / out_right (block samples each).
  void process(std::span<const float> in, std::span<float> out_left, std::span<float> out_right);
  void reset();

 private:
  struct Tap {
    std::size_t delay = 0;
    float left = 0, right = 0;
  };
  double rate_;
  std::vector<float> ring_;
  std::size_t mask_ = 0, write_ = 0;
  std::array<Tap, kTaps> taps_{};
};

}  // namespace earshot::audio
