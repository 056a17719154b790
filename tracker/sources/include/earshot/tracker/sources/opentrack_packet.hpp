// opentrack's "UDP over network" packet: one 48-byte datagram per pose, six
// little-endian IEEE doubles: x, y, z in centimetres, yaw, pitch, roll in
// degrees, yaw then pitch then roll. Its output protocol (proto-udp) sends
// the pose array as it is and its UDP input tracker (tracker-udp) reads it
// back unchanged, so one convention serves both directions: opentrack's own,
// as its trackers fill that array (tracker-rift-140, tracker-steamvr,
// tracker-tobii; docs/OSC.md "opentrack" cites them):
//   +x: the head moves LEFT      +yaw:   turns RIGHT
//   +y: up                       +pitch: looks up
//   +z: BACKWARD (away from the screen)   +roll: tilts LEFT (toward the left shoulder)
// In the audio world frame (+x right, +y up, +z backward; yaw + left, roll +
// toward the right shoulder) that is: x negated, y and z as they are, yaw
// and roll negated, pitch as it is.
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

/// A head pose (audio world frame) as opentrack's packet: the inverse of
/// opentrack_to_pose (angles from earshot::ypr_from_quat, yaw first).
[[nodiscard]] OpentrackPacket pose_to_opentrack(const HeadPose& p);

/// parse_opentrack + opentrack_to_pose, as a PacketDecoder.
[[nodiscard]] std::optional<PoseMessage> decode_opentrack(std::span<const std::uint8_t> bytes, std::string* why);

}  // namespace earshot::tracker
