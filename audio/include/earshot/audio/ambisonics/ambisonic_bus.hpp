// AmbisonicBus: the Ambisonic tier's bus (quality `ambisonic:N`). A
// Renderer made with it (renderer.hpp, source_bus.hpp) hands every source
// here after its distance gain, air absorption and propagation delay; each
// voice's Encoder adds it as a plane wave from its head-relative direction
// into one order-N bus (its gains glide across the block from the last
// block's direction and gain), and one BinauralDecoder turns the bus into
// the two ears once per block.
//
// Cost per source and block: (N+1)^2 gain-curve multiply-adds per sample
// (16 at order 3) instead of the direct path's second delay read and its
// convolution lanes; per block one decode (31 us at order 3, 128 frames,
// docs/AMBISONICS.md). Lost against the direct path: the near field and a
// near source's own ITD (the decoder's filters carry the far-field ITD) and
// the spatial detail above order N.
//
// The bus is head-relative (directions as the head sees them), so it needs
// no rotation: a turning head moves each source's gains, as it moves the
// direct path's blends.
//
// A DSP unit: everything is allocated at construction; the SourceBus calls
// never allocate, lock or do I/O.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "earshot/audio/ambisonics/binaural_decoder.hpp"
#include "earshot/audio/ambisonics/encoder.hpp"
#include "earshot/audio/source_bus.hpp"

namespace earshot::ambisonics {

class AmbisonicBus final : public audio::SourceBus {
 public:
  AmbisonicBus(const DecoderFilters& filters, std::size_t block, std::size_t voices);

  [[nodiscard]] int order() const { return decoder_.order(); }
  [[nodiscard]] std::size_t voices() const override { return encoders_.size(); }
  void reset_voice(std::size_t voice) override;
  void begin_block() override;
  void add(std::size_t voice, const Vec3& direction, float gain, std::span<const float> signal) override;
  void mix_into(std::span<float> left, std::span<float> right) override;

 private:
  std::size_t block_;
  std::vector<Encoder> encoders_;
  BinauralDecoder decoder_;
  std::vector<float> bus_, left_, right_;
};

}  // namespace earshot::ambisonics
