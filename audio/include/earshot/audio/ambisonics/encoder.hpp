// Encoder: a mono signal as a plane wave into an ambiX (ACN, SN3D) bus.
//
// Each update() names the wave's direction (a unit vector in ambiX's frame,
// spherical_harmonics.hpp) at the end of the next block; process() ramps
// every channel's gain linearly from the previous block's to it, so a
// moving source does not step. What an `ambisonic:N` tier runs per source
// (after its distance, air absorption and Doppler), adding into one bus that
// is turned and decoded once.
//
// A DSP unit: allocates at construction only; update() and process() never
// allocate, lock or do I/O.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "earshot/geometry.hpp"

namespace earshot::ambisonics {

class Encoder {
 public:
  Encoder(int order, std::size_t block);

  [[nodiscard]] int order() const { return order_; }
  [[nodiscard]] std::size_t channels() const { return gains_.size(); }
  [[nodiscard]] std::size_t block() const { return block_; }

  /// The direction (ambiX frame; normalised here) and gain at the end of
  /// the next block. The first call also sets its start. A zero or
  /// non-finite direction is ignored.
  void update(const Vec3& direction, float gain = 1.0f);

  /// Forgets the last direction: the next update() starts there, with no
  /// glide (a new source in this encoder).
  void reset() { started_ = false; }

  /// Adds `in` (block() samples) into `bus` (channels() x block() planar).
  void process(std::span<const float> in, std::span<float> bus);

  /// The gains the last block ended with (ACN order).
  [[nodiscard]] std::span<const float> gains() const { return gains_; }

 private:
  int order_;
  std::size_t block_;
  std::vector<float> gains_, target_, ramp_;
  bool started_ = false;
};

}  // namespace earshot::ambisonics
