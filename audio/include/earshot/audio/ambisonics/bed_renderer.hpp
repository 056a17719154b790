// BedRenderer: an ambiX bed to two ears for a tracked listener, the
// SceneRotator and the BinauralDecoder in one unit. What `earshot render
// --ambix`, the C API's bed and the LV2 decoders wrap, and what an
// `ambisonic:N` tier runs once on its bus.
//
//   BedRenderer bed(filters, 128);   // filters: design_binaural_decoder(set, N)
//   per block: bed.set_orientation(listener.orientation);
//              bed.process(in /* (N+1)^2 x 128 planar, ACN SN3D */, left, right);
//
// The orientation given before a block is where the head is at that block's
// end; the rotation glides to it across the block (scene_rotator.hpp). A bed
// is turned by the head, never moved by its position.
//
// A DSP unit: allocates at construction only; set_orientation() and
// process() never allocate, lock or do I/O.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "earshot/audio/ambisonics/binaural_decoder.hpp"
#include "earshot/audio/ambisonics/scene_rotator.hpp"

namespace earshot::ambisonics {

class BedRenderer {
 public:
  BedRenderer(const DecoderFilters& filters, std::size_t block)
      : rotator_(filters.order, block), decoder_(filters, block), turned_(rotator_.channels() * block) {}

  [[nodiscard]] int order() const { return rotator_.order(); }
  [[nodiscard]] std::size_t channels() const { return rotator_.channels(); }
  [[nodiscard]] std::size_t block() const { return rotator_.block(); }

  /// The listener's orientation (audio world frame) at the end of the next block.
  void set_orientation(const Quat& q) { rotator_.update(q); }
  /// in: channels() x block() planar (ACN, SN3D); left, right: block() each, overwritten.
  void process(std::span<const float> in, std::span<float> left, std::span<float> right) {
    rotator_.process(in, turned_);
    decoder_.process(turned_, left, right);
  }
  /// Silence: the filters' tails are dropped; the next orientation starts without a glide.
  void reset(const Quat& q) {
    decoder_.reset();
    rotator_.reset(q);
  }

 private:
  SceneRotator rotator_;
  BinauralDecoder decoder_;
  std::vector<float> turned_;
};

}  // namespace earshot::ambisonics
