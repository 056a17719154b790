// Rotation of an Ambisonic sound field in the spherical-harmonic domain.
//
// A rotation R of the directions (d -> R d) maps the SH coefficients of a
// field linearly and degree by degree: the coefficients of degree l mix
// only among themselves, through a (2l+1) x (2l+1) block. ShRotation builds
// the blocks of the real SHs by the recursion of Ivanic and Ruedenberg
// (J. Phys. Chem. 100, 6342 (1996), with the corrections of 102, 9099
// (1998)): degree 1 is R itself (rows and columns in the order y, z, x of
// ACN channels 1, 2, 3), each higher degree follows from the one below it
// and degree 1. The blocks are the same for SN3D and N3D signals (the two
// differ by one factor per degree), and exact: rotating encoded plane waves
// gives the encoding of the rotated directions (tests/unit/ambisonics).
//
// Head tracking: a bed is a field of plane waves fixed in the world; the
// listener hears it turned by the inverse of the head's orientation.
// field_rotation_for_listener() gives that rotation in ambiX's frame.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <vector>

#include "earshot/geometry.hpp"

namespace earshot::ambisonics {

/// A rotation matrix in ambiX's frame (x ahead, y left, z up), rows first:
/// r[i][j] is output axis i's component of input axis j.
using Mat3 = std::array<std::array<double, 3>, 3>;

/// The rotation matrix of a unit quaternion (w, x, y, z), in its own frame.
[[nodiscard]] Mat3 matrix_from_quat(const Quat& q);

/// The rotation that takes the world's bed to what a listener with this
/// orientation (the head in the audio world frame, as ListenerState has it)
/// hears: a wave from world direction w reaches the head from
/// rotate_inverse(q, w); this is that map in ambiX coordinates.
[[nodiscard]] Mat3 field_rotation_for_listener(const Quat& orientation);

class ShRotation {
 public:
  /// Blocks for degrees 0..order (allocated here), set to the identity.
  explicit ShRotation(int order);

  /// Recomputes every block for rotation `r` (orthonormal). No allocation.
  void set(const Mat3& r);

  [[nodiscard]] int order() const { return order_; }
  /// The block of degree l: (2l+1) x (2l+1), rows first, row and column
  /// i = m + l.
  [[nodiscard]] std::span<const double> block(int l) const;
  /// Entry (m, n) of degree l's block.
  [[nodiscard]] double at(int l, int m, int n) const { return block(l)[static_cast<std::size_t>((m + l) * (2 * l + 1) + n + l)]; }
  /// out = M in over (order + 1)^2 channels (one frame of coefficients).
  void apply(std::span<const double> in, std::span<double> out) const;

 private:
  [[nodiscard]] double& entry(int l, int m, int n) {
    return blocks_[offset_[static_cast<std::size_t>(l)] + static_cast<std::size_t>((m + l) * (2 * l + 1) + n + l)];
  }
  [[nodiscard]] double p(int i, int l, int a, int b) const;

  int order_;
  std::vector<std::size_t> offset_;  // [degree]: first entry of its block
  std::vector<double> blocks_;
};

}  // namespace earshot::ambisonics
