// An Ambisonic bed to two ears for a tracked head: the DSP of the LV2
// decoders `urn:earshot:lv2:ambi-binaural-o1` ... `-o5` (ambi_plugin.cpp),
// kept free of LV2 so tests drive it alone.
//
// A DSP unit in the Resonance way: constructed with the decoder filters of
// one order (designed from an HRTF set, ambisonics/decoder_cache.hpp) and
// the sample rate, it allocates everything then; set_orientation() takes
// the head, process() runs on the audio thread for any number of frames and
// never allocates, locks or does I/O. Inside, a BedRenderer
// (ambisonics/bed_renderer.hpp: the head's rotation, then the binaural
// decoder) works in blocks of kBlock frames through a FIFO: the output is
// the decoded input exactly kBlock frames later (latency(), what the plugin
// reports), whatever frame counts the host passes.
//
// Input: (N+1)^2 channels, ambiX (ACN order, SN3D): x, y, z = ahead, left,
// up. The head's orientation is in the audio world frame (OpenAL's: +x
// right, +y up, -z ahead); the field is fixed in the world, so a head
// turned left hears it turned right.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "earshot/audio/ambisonics/bed_renderer.hpp"
#include "earshot/geometry.hpp"

namespace earshot::lv2 {

class AmbiDecoder {
 public:
  /// The internal block; also the latency in frames.
  static constexpr std::size_t kBlock = 128;

  AmbiDecoder(std::shared_ptr<const ambisonics::DecoderFilters> filters, double sample_rate);

  [[nodiscard]] int order() const { return bed_.order(); }
  [[nodiscard]] std::size_t channels() const { return bed_.channels(); }
  [[nodiscard]] std::size_t latency() const { return kBlock; }
  [[nodiscard]] double sample_rate() const { return rate_; }

  /// The head's orientation in the world, heard from the next internal block.
  void set_orientation(const Quat& head) { head_ = normalised(head).value_or(Quat{1, 0, 0, 0}); }
  /// `frames` frames of the channels() inputs (null: silence) to `left` and
  /// `right`, delayed by latency(). An input may alias an output.
  void process(const float* const* in, float* left, float* right, std::size_t frames);
  /// Silence in the FIFO and the filters' tails (after a transport jump).
  void reset();

 private:
  void render_block();

  double rate_;
  std::shared_ptr<const ambisonics::DecoderFilters> filters_;
  ambisonics::BedRenderer bed_;
  Quat head_{1, 0, 0, 0};
  std::vector<float> in_, out_l_, out_r_;  // the FIFO: kBlock per channel
  std::size_t fill_ = 0;
};

}  // namespace earshot::lv2
