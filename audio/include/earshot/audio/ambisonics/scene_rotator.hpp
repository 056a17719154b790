// SceneRotator: turns an Ambisonic bed (ambiX, order N) by the listener's
// head orientation, block by block, without clicks.
//
// Signals are planar blocks: channel c's block() samples at
// [c * block(), (c + 1) * block()), ACN order, (N + 1)^2 channels. SN3D or
// N3D alike (the rotation does not mix degrees).
//
// Each update() names the head's orientation at the end of the next block
// (the audio world frame, as ListenerState::orientation). process() glides
// from the previous block's rotation to it: every entry of the SH rotation
// matrix moves linearly across the block, so the rotation each sample
// hears is continuous and consecutive blocks join without a step. Between
// two poses 0.96 degree apart (360 deg/s at 128 frames, 48 kHz) the linear
// blend of two rotation matrices is within 9e-4 (largest entry, order 5) of
// the rotation half-way (tests/unit/ambisonics/test_rotation.cpp);
// tests/bench/ambi_cues.cpp measures what a 500 Hz tone ahead gives above
// 2 kHz while the head turns. A head that did not move costs one matrix per
// block; a moving one two.
//
// A DSP unit: everything is allocated at construction; update() and
// process() never allocate, lock or do I/O. A non-finite or zero quaternion
// is ignored (the previous orientation stays).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "earshot/audio/ambisonics/sh_rotation.hpp"
#include "earshot/geometry.hpp"

namespace earshot::ambisonics {

class SceneRotator {
 public:
  SceneRotator(int order, std::size_t block);

  [[nodiscard]] int order() const { return order_; }
  [[nodiscard]] std::size_t channels() const { return channels_; }
  [[nodiscard]] std::size_t block() const { return block_; }

  /// The listener's orientation at the end of the next block. The first
  /// call (and the first after reset()) also sets where that block starts.
  void update(const Quat& listener_orientation);
  /// Starts the next block at `listener_orientation` with no glide.
  void reset(const Quat& listener_orientation);

  /// in, out: channels() x block() planar; may not overlap.
  void process(std::span<const float> in, std::span<float> out);

 private:
  void load(const Quat& q, std::vector<float>& dense);

  int order_;
  std::size_t channels_, block_;
  ShRotation rotation_;
  // Per degree, its block's entries (rows first), concatenated: the matrix
  // at the start of the block (from_) and at its end (to_).
  std::vector<float> from_, to_;
  std::vector<float> ramp_;  // (i + 1) / block
  bool started_ = false, moving_ = false;
};

}  // namespace earshot::ambisonics
