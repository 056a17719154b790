// The gain curve of a crossfade from one renderer to another (an HRTF set
// switched while playing): both render the same input, the output moves from
// the old one's to the new one's.
//
// Raised cosine, not a straight line: a linear fade's slope jumps at both
// ends, and those corners spread a tone's sidebands far from it (with a
// 500 Hz tone and a 512-frame fade at 48 kHz, -80 dB above 2 kHz); the
// cosine's slope starts and ends at zero, so its sidebands fall off faster.
// The two gains sum to one: the renderers' outputs are of the same source
// through similar filters (correlated), so amplitudes, not powers, add.
#pragma once

#include <cmath>
#include <cstddef>
#include <numbers>

namespace earshot::audio {

/// The new renderer's gain at frame `t` of a switch that warms up for
/// `warm` frames (the old one alone is heard) and then fades over `fade`
/// frames; the old renderer gets 1 minus this.
[[nodiscard]] inline float crossfade_gain(std::size_t t, std::size_t warm, std::size_t fade) {
  if (t < warm) return 0.0f;
  if (t >= warm + fade) return 1.0f;
  const double x = (static_cast<double>(t - warm) + 0.5) / static_cast<double>(fade);
  return static_cast<float>(0.5 - 0.5 * std::cos(std::numbers::pi * x));
}

}  // namespace earshot::audio
