// SourceBus: where a Renderer sends its sources instead of the direction
// bank when it renders the Ambisonic tier (quality `ambisonic:N`).
//
// Each source keeps everything the direct path gives it before the HRTF:
// its distance gain, cone, air absorption and propagation delay (Doppler);
// then, instead of being panned into the measured directions' convolvers,
// it is handed here once per block with its direction as the head sees it
// and its gain at the block's end. The bus (an Ambisonic encoder per voice
// into one order-N bus, decoded once per block:
// earshot/audio/ambisonics/ambisonic_bus.hpp) mixes the result into the
// renderer's mix before the limiter.
//
// An interface in the renderer's library so the renderer does not depend on
// the Ambisonics library (which builds on it). Implementations allocate at
// construction only; every call below runs on the audio thread inside
// Renderer::render() and must not allocate, lock or do I/O.
#pragma once

#include <cstddef>
#include <span>

#include "earshot/geometry.hpp"

namespace earshot::audio {

class SourceBus {
 public:
  virtual ~SourceBus() = default;

  /// Voices it can take (at least the renderer's max_sources).
  [[nodiscard]] virtual std::size_t voices() const = 0;
  /// Voice `voice` holds a new source: its next add() starts where it is,
  /// with no glide from the voice's previous source.
  virtual void reset_voice(std::size_t voice) = 0;
  /// Starts a block: the bus is silent.
  virtual void begin_block() = 0;
  /// Adds voice `voice`'s block `signal` from `direction` (a unit vector in
  /// the head's frame, SOFA's and ambiX's axes: x ahead, y left, z up) at
  /// `gain`, both reached at the block's end (a glide from the voice's last
  /// block).
  virtual void add(std::size_t voice, const Vec3& direction, float gain, std::span<const float> signal) = 0;
  /// Decodes the block's bus and adds it into `left` and `right`.
  virtual void mix_into(std::span<float> left, std::span<float> right) = 0;
};

}  // namespace earshot::audio
