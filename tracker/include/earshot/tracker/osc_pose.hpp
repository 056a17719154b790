// Head poses over OSC (Open Sound Control, decoded by liblo). Addresses, in
// the audio world frame (+x right, +y up, -z ahead; metres; degrees; yaw
// positive turns left, pitch positive looks up, roll positive tilts toward the
// right shoulder); every number may be float32, float64 or int32:
//   /earshot/pose/ypr   x y z yaw pitch roll     position and Euler angles
//   /earshot/pose/quat  x y z qw qx qy qz        position and unit quaternion
//   /earshot/ypr        yaw pitch roll            orientation only (at the origin)
//   /earshot/quat       qw qx qy qz               orientation only
//   /earshot/recenter   (no arguments)            the next pose becomes neutral
// Anything else (another address, wrong types or count, NaN, a position
// beyond 10 m, a quaternion far from unit length, a bundle) is dropped with
// a reason.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "earshot/tracker/udp_pose_source.hpp"

namespace earshot::tracker {

inline constexpr std::uint16_t kOscDefaultPort = 9000;

/// Decodes one OSC datagram (a PacketDecoder).
[[nodiscard]] std::optional<PoseMessage> decode_osc(std::span<const std::uint8_t> bytes, std::string* why);

/// One OSC message with float64 arguments, as bytes (tests, tools).
[[nodiscard]] std::vector<std::uint8_t> encode_osc(const std::string& path, std::span<const double> args);

}  // namespace earshot::tracker
