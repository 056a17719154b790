#include "earshot/audio/ambisonics/sh_rotation.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"

namespace earshot::ambisonics {

Mat3 matrix_from_quat(const Quat& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

Mat3 field_rotation_for_listener(const Quat& orientation) {
  // Column j: where ambiX axis j of the world lands as the head hears it.
  Mat3 r{};
  for (std::size_t j = 0; j < 3; ++j) {
    Vec3 e{0, 0, 0};
    e[j] = 1.0;
    const Vec3 heard = ambix_from_world(rotate_inverse(orientation, world_from_ambix(e)));
    for (std::size_t i = 0; i < 3; ++i) r[i][j] = heard[i];
  }
  return r;
}

ShRotation::ShRotation(int order) : order_(order) {
  if (order < 0 || order > kMaxOrder)
    throw std::invalid_argument("ShRotation: order " + std::to_string(order) + " outside 0.." +
                                std::to_string(kMaxOrder));
  std::size_t total = 0;
  for (int l = 0; l <= order; ++l) {
    offset_.push_back(total);
    total += static_cast<std::size_t>((2 * l + 1) * (2 * l + 1));
  }
  blocks_.assign(total, 0.0);
  for (int l = 0; l <= order; ++l)
    for (int m = -l; m <= l; ++m) entry(l, m, m) = 1.0;
}

std::span<const double> ShRotation::block(int l) const {
  const auto n = static_cast<std::size_t>((2 * l + 1) * (2 * l + 1));
  return std::span<const double>(blocks_).subspan(offset_[static_cast<std::size_t>(l)], n);
}

// Ivanic and Ruedenberg's P: degree 1's entry (i, +-1 or 0) times degree
// l - 1's entry at (a, b), b = +-l handled by the two degree-1 terms.
double ShRotation::p(int i, int l, int a, int b) const {
  const double r1 = at(1, i, 1), rm1 = at(1, i, -1), r0 = at(1, i, 0);
  if (b == l) return r1 * at(l - 1, a, l - 1) - rm1 * at(l - 1, a, -l + 1);
  if (b == -l) return r1 * at(l - 1, a, -l + 1) + rm1 * at(l - 1, a, l - 1);
  return r0 * at(l - 1, a, b);
}

void ShRotation::set(const Mat3& r) {
  if (order_ == 0) return;
  // Degree 1: ACN 1, 2, 3 are y, z, x (m = -1, 0, 1).
  constexpr std::array<std::size_t, 3> axis{1, 2, 0};
  for (int m = -1; m <= 1; ++m)
    for (int n = -1; n <= 1; ++n) entry(1, m, n) = r[axis[static_cast<std::size_t>(m + 1)]][axis[static_cast<std::size_t>(n + 1)]];
  for (int l = 2; l <= order_; ++l) {
    for (int m = -l; m <= l; ++m) {
      const int am = m < 0 ? -m : m;
      const double d = m == 0 ? 1.0 : 0.0;
      for (int n = -l; n <= l; ++n) {
        const int an = n < 0 ? -n : n;
        const double den = an == l ? double(2 * l) * double(2 * l - 1) : double(l + n) * double(l - n);
        const double u = std::sqrt(double(l + m) * double(l - m) / den);
        const double v = 0.5 * std::sqrt((1.0 + d) * double(l + am - 1) * double(l + am) / den) * (1.0 - 2.0 * d);
        const double w = -0.5 * std::sqrt(double(l - am - 1) * double(l - am) / den) * (1.0 - d);
        double value = 0.0;
        if (u != 0.0) value += u * p(0, l, m, n);
        if (v != 0.0) {
          double vv;
          if (m == 0) {
            vv = p(1, l, 1, n) + p(-1, l, -1, n);
          } else if (m > 0) {
            const double d1 = m == 1 ? 1.0 : 0.0;
            vv = p(1, l, m - 1, n) * std::sqrt(1.0 + d1) - p(-1, l, -m + 1, n) * (1.0 - d1);
          } else {
            const double d1 = m == -1 ? 1.0 : 0.0;
            vv = p(1, l, m + 1, n) * (1.0 - d1) + p(-1, l, -m - 1, n) * std::sqrt(1.0 + d1);
          }
          value += v * vv;
        }
        if (w != 0.0) {
          const double ww = m > 0 ? p(1, l, m + 1, n) + p(-1, l, -m - 1, n) : p(1, l, m - 1, n) - p(-1, l, -m + 1, n);
          value += w * ww;
        }
        entry(l, m, n) = value;
      }
    }
  }
}

void ShRotation::apply(std::span<const double> in, std::span<double> out) const {
  for (int l = 0; l <= order_; ++l) {
    const auto b = block(l);
    const auto first = static_cast<std::size_t>(l * l), size = static_cast<std::size_t>(2 * l + 1);
    for (std::size_t i = 0; i < size; ++i) {
      double acc = 0.0;
      for (std::size_t j = 0; j < size; ++j) acc += b[i * size + j] * in[first + j];
      out[first + i] = acc;
    }
  }
}

}  // namespace earshot::ambisonics
