// Head poses over OSC (Open Sound Control, messages decoded by liblo), as
// Earshot's own addresses and as the head trackers in the field send them to
// SPARTA and to the IEM plug-in suite's SceneRotator. docs/OSC.md has the
// full table, the sources of each convention and oscsend examples.
//
// Earshot's audio world frame: +x right, +y up, -z ahead; metres; degrees;
// yaw positive turns left, pitch positive looks up, roll positive tilts
// toward the right shoulder. Every number may be float32, float64 or int32.
//
// Earshot (absolute, stateless):
//   /earshot/pose/ypr   x y z yaw pitch roll     position and Euler angles
//   /earshot/pose/quat  x y z qw qx qy qz        position and unit quaternion
//   /earshot/ypr        yaw pitch roll            orientation only (at the origin)
//   /earshot/quat       qw qx qy qz               orientation only
//   /earshot/recenter   (no arguments)            the next pose becomes neutral
// SPARTA (Spatial Audio Framework frame: x ahead, y left, z up; the values
// are the HEAD's orientation, yaw-pitch-roll intrinsic; right-hand rule, so
// positive pitch nods DOWN):
//   /ypr yaw pitch roll   -> Earshot yaw, -pitch, roll
//   /yaw v, /pitch v, /roll v   one angle; the others kept
//   /quaternion w x y z   -> Earshot (w, -y, z, -x)
//   /xyz x y z            position in metres -> Earshot (-y, z, -x); orientation kept
// IEM SceneRotator (same frame; the values are the SCENE's rotation, extrinsic
// yaw then pitch then roll, i.e. the inverse of the head's orientation):
//   /SceneRotator/ypr yaw pitch roll  -> Earshot yaw -yaw, pitch +pitch, roll -roll
//   /SceneRotator/yaw v, /pitch v, /roll v   one angle; the others kept
//   /SceneRotator/quaternions w x y z -> the inverse, in Earshot's axes: (w, y, -z, x)
//   /SceneRotator/qw v, /qx v, /qy v, /qz v  one component; a pose once the
//                                            four make a unit quaternion
// A single-axis message updates the decoder's state for its sender convention
// and yields the whole pose; SPARTA poses carry the last /xyz position.
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
// Anything else (another address, wrong types or count, NaN, an angle beyond
// 720 degrees, a position beyond 10 m, a quaternion far from unit length) is
// dropped with a reason.
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
  struct Euler {
    double yaw = 0, pitch = 0, roll = 0;  ///< degrees, as the sender means them
  };
  std::optional<PoseMessage> message(std::span<const std::uint8_t> bytes, std::string* why);
  std::optional<PoseMessage> bundle(std::span<const std::uint8_t> bytes, std::string* why);
  /// One message's meaning; `numbers` is null when an argument is not a number.
  std::optional<PoseMessage> handle(std::string_view path, std::string_view types, const std::vector<double>* numbers,
                                    std::string* why);
  std::optional<PoseMessage> sparta(std::string_view path, const std::vector<double>& v, std::string* why);
  std::optional<PoseMessage> scene_rotator(std::string_view path, const std::vector<double>& v, std::string* why);

  Euler sparta_;
  Vec3 sparta_position_m_ = Vec3::Zero();  ///< Earshot axes
  Euler scene_rotator_;
  std::array<double, 4> scene_rotator_q_{1, 0, 0, 0};  ///< w x y z as sent
};

/// One OSC message with float64 arguments, as bytes (tests, tools).
[[nodiscard]] std::vector<std::uint8_t> encode_osc(const std::string& path, std::span<const double> args);

/// One OSC message with float32 arguments, as bytes (what oscsend's "f" sends).
[[nodiscard]] std::vector<std::uint8_t> encode_osc_float(const std::string& path, std::span<const float> args);

/// A bundle (timetag "immediately") holding these elements, each a message or
/// a bundle as bytes (tests, tools).
[[nodiscard]] std::vector<std::uint8_t> encode_osc_bundle(std::span<const std::vector<std::uint8_t>> elements);

}  // namespace earshot::tracker
