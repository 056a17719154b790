#include "earshot/tracker/sources/opentrack_packet.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>


namespace earshot::tracker {
namespace {

double le_double(std::span<const std::uint8_t> b) {
  std::uint64_t u = 0;
  for (std::size_t i = 0; i < 8; ++i) u |= static_cast<std::uint64_t>(b[i]) << (8 * i);
  return std::bit_cast<double>(u);
}

bool fail(std::string* why, std::string msg) {
  if (why) *why = std::move(msg);
  return false;
}

}  // namespace

std::optional<OpentrackPacket> parse_opentrack(std::span<const std::uint8_t> b, std::string* why) {
  if (b.size() != kOpentrackPacketSize) {
    fail(why, "opentrack packet of " + std::to_string(b.size()) + " bytes, expected 48");
    return std::nullopt;
  }
  std::array<double, 6> v{};
  for (std::size_t i = 0; i < 6; ++i) v[i] = le_double(b.subspan(8 * i, 8));
  static constexpr const char* kNames[] = {"x", "y", "z", "yaw", "pitch", "roll"};
  for (std::size_t i = 0; i < 6; ++i) {
    const double limit = i < 3 ? kMaxPositionM * 100.0 : 360.0;
    if (!std::isfinite(v[i]) || std::abs(v[i]) > limit) {
      fail(why, std::string("opentrack packet: ") + kNames[i] + " = " + std::to_string(v[i]) + " is not a plausible value");
      return std::nullopt;
    }
  }
  return OpentrackPacket{v[0], v[1], v[2], v[3], v[4], v[5]};
}

std::array<std::uint8_t, kOpentrackPacketSize> encode_opentrack(const OpentrackPacket& p) {
  std::array<std::uint8_t, kOpentrackPacketSize> out{};
  const std::array<double, 6> v{p.x_cm, p.y_cm, p.z_cm, p.yaw_deg, p.pitch_deg, p.roll_deg};
  for (std::size_t i = 0; i < 6; ++i) {
    const auto u = std::bit_cast<std::uint64_t>(v[i]);
    for (std::size_t k = 0; k < 8; ++k) out[8 * i + k] = static_cast<std::uint8_t>(u >> (8 * k));
  }
  return out;
}

HeadPose opentrack_to_pose(const OpentrackPacket& p) {
  constexpr double deg = std::numbers::pi / 180.0;
  HeadPose d;
  // opentrack: x left, z backward; yaw right, roll left (the header above).
  d.position = to_common(Vec3(Vec3(-p.x_cm, p.y_cm, p.z_cm) * 0.01));
  d.orientation = quat_from_ypr(-p.yaw_deg * deg, p.pitch_deg * deg, -p.roll_deg * deg);
  d.state = PoseState::tracking;
  return d;
}

OpentrackPacket pose_to_opentrack(const HeadPose& p) {
  constexpr double deg = 180.0 / std::numbers::pi;
  const YawPitchRoll a = ypr_from_quat(p.orientation);
  return {-p.position[0] * 100.0, p.position[1] * 100.0, p.position[2] * 100.0,
          -a.yaw * deg,           a.pitch * deg,         -a.roll * deg};
}

std::optional<PoseMessage> decode_opentrack(std::span<const std::uint8_t> bytes, std::string* why) {
  const auto p = parse_opentrack(bytes, why);
  if (!p) return std::nullopt;
  return PoseMessage{opentrack_to_pose(*p), false};
}

}  // namespace earshot::tracker
