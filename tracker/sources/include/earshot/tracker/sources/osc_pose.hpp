// Head poses over OSC (Open Sound Control, messages decoded by liblo), as
// Earshot's own addresses and as the head trackers in the field send them to
// SPARTA (its rotator, binaural and 6DoFconv plug-ins) and to the IEM
// plug-in suite's SceneRotator; and the same conventions the other way, for
// the pose senders (tracker/send). docs/OSC.md has the full table, the
// sources of each convention and oscsend examples.
//
// Earshot's audio world frame: +x right, +y up, -z ahead; metres; degrees;
// yaw positive turns left, pitch positive looks up, roll positive tilts
// toward the right shoulder. Every number may be float32, float64 or int32.
// Addresses match in any case (/SCENEROTATOR/YPR too), as IEM's plug-ins
// match theirs.
//
// Earshot (absolute, stateless):
//   /earshot/pose/ypr   x y z yaw pitch roll     position and Euler angles
//   /earshot/pose/quat  x y z qw qx qy qz        position and quaternion
//   /earshot/ypr        yaw pitch roll            orientation only (at the origin)
//   /earshot/quat       qw qx qy qz               orientation only
//   /earshot/recenter   (no arguments)            the next pose becomes neutral
// SPARTA (Spatial Audio Framework frame: x ahead, y left, z up; the values
// are the HEAD's orientation, yaw-pitch-roll intrinsic; right-hand rule, so
// positive pitch nods DOWN):
//   /ypr yaw pitch roll   -> Earshot yaw, -pitch, roll
//   /yaw v, /pitch v, /roll v   one angle; the others kept
//   /quaternion w x y z   -> Earshot (w, -y, z, -x); also 6DoFconv's /quat
//   /qw v, /qx v, /qy v, /qz v  one component (the rotator's); the others kept
//   /xyz x y z            position in metres -> Earshot (-y, z, -x); orientation kept
//   /xyzquat x y z w qx qy qz, /xyzypr x y z yaw pitch roll   6DoFconv's both at once
// IEM SceneRotator (same frame; the values are the SCENE's rotation, extrinsic
// yaw then pitch then roll, i.e. the inverse of the head's orientation):
//   /SceneRotator/ypr yaw pitch roll  -> Earshot yaw -yaw, pitch +pitch, roll -roll
//   /SceneRotator/yaw v, /pitch v, /roll v   one angle; the others kept
//   /SceneRotator/quaternions w x y z -> the inverse, in Earshot's axes: (w, y, -z, x)
//   /SceneRotator/qw v, /qx v, /qy v, /qz v  one component; a pose once the
//                                            four are near unit length
// A single-axis message updates the decoder's state for its sender convention
// and yields the whole pose; SPARTA poses carry the last /xyz position.
//
// Numbers as each receiver takes them: quaternions are normalised (only one
// shorter than kOscMinQuaternionNorm, or not finite, is refused); angles of
// Earshot and SPARTA are periodic (any finite value, wrapped as SAF's sines
// and cosines wrap them); SceneRotator's angles are clamped to -180..180 and
// its quaternion components to -1..1, as its parameters are.
//
// Bundles ("#bundle\0", an 8-byte timetag, then elements: an int32 big-endian
// size and a message or a nested bundle) are decoded element by element, in
// order; timetags are ignored (everything applies now). The last pose in a
// bundle wins; a recenter anywhere in it counts. Nesting deeper than
// kOscMaxBundleDepth, more than kOscMaxBundleElements elements, or an element
// size that is not a positive multiple of 4 within the packet drops the whole
// bundle, with the element named, before any state changes; an element that
// is well formed but not ours is skipped.
//
// Anything else (another address, wrong types or count, NaN, a position
// beyond 10 m, a quaternion with no direction) is dropped with a reason.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "earshot/tracker/sources/udp_pose_source.hpp"

namespace earshot::tracker {

inline constexpr std::uint16_t kOscDefaultPort = 9000;
/// A bundle inside a bundle inside ... : at most this many levels.
inline constexpr int kOscMaxBundleDepth = 8;
/// Messages and bundles in one datagram, all levels together.
inline constexpr int kOscMaxBundleElements = 64;
/// A quaternion shorter than this has no direction to normalise to.
inline constexpr double kOscMinQuaternionNorm = 1e-3;

// ---- The conventions, both ways (degrees; quaternions w x y z) ----

/// The Spatial Audio Framework's axes (x ahead, y left, z up) in Earshot's,
/// and back: a proper rotation, so quaternion vector parts map the same way.
[[nodiscard]] Vec3 saf_to_earshot(double x, double y, double z);
[[nodiscard]] Vec3 earshot_to_saf(const Vec3& v);

/// SPARTA: the head's yaw, pitch, roll about SAF's axes (intrinsic, right-hand
/// rule: pitch + nods down) as Earshot's head orientation, and back
/// (yaw and roll in (-180, 180], pitch in [-90, 90]).
[[nodiscard]] Quat sparta_head(double yaw, double pitch, double roll);
[[nodiscard]] std::array<double, 3> sparta_ypr(const Quat& head);
/// SPARTA's /quaternion (w x y z of the head about SAF's axes) of a head.
[[nodiscard]] std::array<double, 4> sparta_quaternion(const Quat& head);

/// SceneRotator: the scene's rotation Rx(roll) Ry(pitch) Rz(yaw) (its default
/// sequence) as the head that hears it (the inverse), and back.
[[nodiscard]] Quat scene_rotator_head(double yaw, double pitch, double roll);
[[nodiscard]] std::array<double, 3> scene_rotator_ypr(const Quat& head);
/// /SceneRotator/quaternions (w x y z of the scene's rotation) of a head.
[[nodiscard]] std::array<double, 4> scene_rotator_quaternions(const Quat& head);

/// Decodes OSC datagrams into poses; holds what single-axis messages need
/// (the last angles, quaternion components and position of each sender
/// convention). One per socket; not thread-safe.
class OscPoseDecoder {
 public:
  /// One datagram (a message or a bundle); nullopt with `why` set when
  /// nothing in it is ours or it is malformed.
  [[nodiscard]] std::optional<PoseMessage> decode(std::span<const std::uint8_t> bytes, std::string* why);

  /// A PacketDecoder for UdpPoseSource that owns a fresh decoder.
  [[nodiscard]] static PacketDecoder packet_decoder();

 private:
  std::optional<PoseMessage> message(std::span<const std::uint8_t> bytes, std::string* why);
  std::optional<PoseMessage> bundle(std::span<const std::uint8_t> bytes, std::string* why);
  /// One message's meaning; `numbers` is null when an argument is not a number.
  std::optional<PoseMessage> handle(std::string_view path, std::string_view types, const std::vector<double>* numbers,
                                    std::string* why);
  /// `p`: the address in lower case; `path`: as sent (for messages).
  std::optional<PoseMessage> sparta(const std::string& p, std::string_view path, const std::vector<double>& v,
                                    std::string* why);
  std::optional<PoseMessage> scene_rotator(const std::string& p, std::string_view path, const std::vector<double>& v,
                                           std::string* why);

  std::array<double, 3> sparta_{};                ///< yaw, pitch, roll (degrees) as SPARTA means them
  std::array<double, 4> sparta_q_{1, 0, 0, 0};    ///< w x y z about SAF's axes, as sent
  Vec3 sparta_position_m_ = Vec3::Zero();         ///< Earshot axes
  std::array<double, 3> scene_rotator_{};         ///< yaw, pitch, roll of the scene
  std::array<double, 4> scene_rotator_q_{1, 0, 0, 0};  ///< w x y z as sent (clamped to -1..1)
};

/// One OSC message with float64 arguments, as bytes (tests, tools).
[[nodiscard]] std::vector<std::uint8_t> encode_osc(const std::string& path, std::span<const double> args);

/// One OSC message with float32 arguments, as bytes (what oscsend's "f" sends).
[[nodiscard]] std::vector<std::uint8_t> encode_osc_float(const std::string& path, std::span<const float> args);

/// The same message written into `out` without allocating (the pose
/// senders, on the tracker thread): the address padded to 4 bytes, the type
/// tags ",f..." padded, then each float big-endian. Returns the bytes
/// written, or 0 when `out` is too small or the address is not '/'-led.
std::size_t write_osc_floats(std::span<std::uint8_t> out, std::string_view address, std::span<const float> args);

/// A bundle (timetag "immediately") holding these elements, each a message or
/// a bundle as bytes (tests, tools).
[[nodiscard]] std::vector<std::uint8_t> encode_osc_bundle(std::span<const std::vector<std::uint8_t>> elements);

}  // namespace earshot::tracker
