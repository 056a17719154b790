// Real spherical harmonics as Ambisonics uses them, and the conventions of
// Ambisonic signals.
//
// Channel order: ACN. Channel n = l^2 + l + m holds degree (order) l and
// index m (-l..l); an order-N signal has (N+1)^2 channels.
//
// Normalisation: SN3D unless said otherwise (ambiX, Nachbar et al. 2011):
//   Y_l^m(az, el) = N_l^|m| P_l^|m|(sin el) * { cos(m az)   m >= 0
//                                             { sin(|m| az) m < 0
//   N_l^m = sqrt((2 - delta_m0) (l - m)! / (l + m)!)   (SN3D)
// with P_l^m the associated Legendre function WITHOUT the Condon-Shortley
// phase (-1)^m. So W = 1, and the first-order channels of a plane wave are
// Y = sin az cos el, Z = sin el, X = cos az cos el. N3D multiplies degree l
// by sqrt(2l + 1) (orthonormal up to 4 pi); FuMa (Furse-Malham, orders <= 3)
// reorders the channels (W X Y Z R S T U V K L M N O P Q) and scales each to
// a maximum of 1 over the sphere ("maxN"), except W, which is -3 dB
// (1/sqrt 2).
//
// Directions: ambiX's x, y, z are ahead, left, up: the audio world frame's
// (OpenAL's: +x right, +y up, -z ahead) -z, -x and +y, and SOFA's x, y, z
// (so a SOFA azimuth/elevation is an ambiX one: azimuth counter-clockwise
// from ahead, 90 deg = left). Functions here take unit vectors in the ambiX
// frame; ambix_from_world() and ambix_from_sofa() make them.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "earshot/geometry.hpp"

namespace earshot::ambisonics {

/// The highest order any unit here takes (64 channels).
inline constexpr int kMaxOrder = 7;
/// FuMa is defined up to third order.
inline constexpr int kMaxFumaOrder = 3;

/// Channels of an order-N signal: (N + 1)^2.
[[nodiscard]] constexpr std::size_t channel_count(int order) {
  return static_cast<std::size_t>(order + 1) * static_cast<std::size_t>(order + 1);
}
/// The ACN channel of degree l, index m.
[[nodiscard]] constexpr std::size_t acn(int l, int m) { return static_cast<std::size_t>(l * l + l + m); }
/// The degree of ACN channel n.
[[nodiscard]] int degree_of(std::size_t n);
/// The order of a signal with `channels` channels, or -1 when that is not
/// (N + 1)^2 for an N in 0..kMaxOrder.
[[nodiscard]] int order_from_channels(std::size_t channels);

/// A unit vector in ambiX's frame from one in the audio world frame.
[[nodiscard]] constexpr Vec3 ambix_from_world(const Vec3& w) { return {-w[2], -w[0], w[1]}; }
/// The inverse of ambix_from_world.
[[nodiscard]] constexpr Vec3 world_from_ambix(const Vec3& a) { return {-a[1], a[2], -a[0]}; }
/// The unit vector of a SOFA / ambiX azimuth and elevation (radians).
[[nodiscard]] Vec3 ambix_from_sofa(double azimuth, double elevation);

/// SN3D real spherical harmonics up to `order` (0..kMaxOrder) of the unit
/// vector `d` (ambiX frame; not checked for length), into out[0 .. (N+1)^2).
/// The gains of an ambiX encoder for a plane wave from d. No trigonometry,
/// no allocation.
void real_sh(int order, const Vec3& d, std::span<double> out);
void real_sh(int order, const Vec3& d, std::span<float> out);

/// Conventions an Ambisonic signal may come in.
enum class Convention {
  ambix,  ///< ACN order, SN3D
  n3d,    ///< ACN order, N3D
  fuma,   ///< Furse-Malham order and maxN gains, orders 0..3
};
/// "ambix", "n3d", "fuma".
[[nodiscard]] std::string_view convention_name(Convention c);

/// How to make ambiX (ACN, SN3D) channel n from a signal in another
/// convention: ambix[n] = gain[n] * other[source[n]].
struct ChannelMap {
  std::vector<std::size_t> source;
  std::vector<double> gain;
};
/// The map from `from` to ambiX at `order`. Throws std::invalid_argument for
/// FuMa above order 3 or an order outside 0..kMaxOrder.
[[nodiscard]] ChannelMap to_ambix(Convention from, int order);
/// The map from ambiX to `to`: other[n] = gain[n] * ambix[source[n]].
[[nodiscard]] ChannelMap from_ambix(Convention to, int order);

}  // namespace earshot::ambisonics
