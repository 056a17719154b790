// opentrack's "UDP over network" output: one 48-byte datagram per pose, six
// little-endian IEEE doubles: x, y, z in centimetres, yaw, pitch, roll in
// degrees. opentrack's axes: x right, y up, z forward (towards the screen);
// yaw positive to the right, pitch positive up, roll positive to the right.
// We map it into the audio world frame (+x right, +y up, -z ahead; positive
// yaw turns left): x, y as they are, z negated, yaw negated.
#pragma once

#include <optional>
#include <span>
#include <string>

#include "earshot/tracker/sources/udp_pose_source.hpp"

namespace earshot::tracker {

inline constexpr std::size_t kOpentrackPacketSize = 48;
inline constexpr std::uint16_t kOpentrackDefaultPort = 4242;

struct OpentrackPacket {
  double x_cm = 0, y_cm = 0, z_cm = 0, yaw_deg = 0, pitch_deg = 0, roll_deg = 0;
};

/// The six doubles of one datagram; nullopt with `why` when the size is not
/// 48 bytes, a value is not finite, the position is beyond 10 m or an angle
/// beyond +-360 degrees.
[[nodiscard]] std::optional<OpentrackPacket> parse_opentrack(std::span<const std::uint8_t> bytes, std::string* why);

/// The 48 bytes of a packet (tests, tools).
[[nodiscard]] std::array<std::uint8_t, kOpentrackPacketSize> encode_opentrack(const OpentrackPacket& p);

/// A parsed packet as a head pose in the audio world frame.
[[nodiscard]] HeadPose opentrack_to_pose(const OpentrackPacket& p);

/// parse_opentrack + opentrack_to_pose, as a PacketDecoder.
[[nodiscard]] std::optional<PoseMessage> decode_opentrack(std::span<const std::uint8_t> bytes, std::string* why);

}  // namespace earshot::tracker
