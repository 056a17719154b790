// Motion paths: where a moving source is at time t (seconds from the start
// of the render). A path replaces a source's fixed `position`; the renderer
// is given the path's position once per block, so the source's velocity, and
// with it the Doppler shift (through the propagation delay), follows.
//
// Frame: OpenAL's world frame (+x right, +y up, -z ahead), metres, seconds.
//
// Paths (Scene JSON: "path": {"type": ..., fields}):
//   circle    {centre, radius, plane: "xz"|"xy"|"yz" or normal: [x,y,z],
//              period_s or speed_mps, phase_deg, direction: "ccw"|"cw", start_s}
//             position = centre + radius (cos a u + sin a v), with
//             a = phase + 2 pi (t - start_s) / period (negated for "cw").
//             u, v span the plane and v = normal x u, so "ccw" turns
//             counter-clockwise seen from the tip of the normal:
//               "xz" (normal +y, the horizontal plane): u = +x, v = -z;
//                    phase 0 right, 90 ahead, 180 left, 270 behind.
//               "xy" (normal +z, the frontal plane): u = +x, v = +y;
//                    phase 0 right, 90 above, 180 left, 270 below.
//               "yz" (normal +x, the median plane): u = -z, v = +y;
//                    phase 0 ahead, 90 above, 180 behind, 270 below.
//             Any other normal: u is +x made perpendicular to it (-z when
//             the normal is near x).
//   line      {from, to, speed_mps, mode: "once"|"loop"|"ping-pong", start_s}
//             from `from` to `to` at speed_mps; "once" then stays at `to`,
//             "loop" jumps back to `from` (put both ends far away: the jump
//             is a jump in propagation delay), "ping-pong" turns round.
//   waypoints {points: [[x,y,z], ...] (2 or more), speed_mps, loop, start_s}
//             along straight segments at speed_mps; loop: true goes on from
//             the last point back to the first and round again, false stays
//             at the last point.
// Before start_s (default 0) every path holds its starting point.
#pragma once

#include <array>
#include <optional>
#include <string_view>
#include <variant>
#include <vector>

#include "earshot/geometry.hpp"

namespace earshot::scenes {

struct CirclePath {
  Vec3 centre{0, 0, 0};
  double radius = 1.0;            ///< metres, > 0
  Vec3 normal{0, 1, 0};         ///< axis of the circle's plane (any length > 0)
  double period_s = 10.0;         ///< one turn
  double phase_deg = 0.0;         ///< angle at start_s
  bool clockwise = false;         ///< seen from the tip of the normal
  double start_s = 0.0;
};

struct LinePath {
  enum class Mode { once, loop, ping_pong };
  Vec3 from{-10, 0, -2}, to{10, 0, -2};
  double speed_mps = 1.0;         ///< > 0
  Mode mode = Mode::once;
  double start_s = 0.0;
};

struct WaypointPath {
  std::vector<Vec3> points;     ///< at least two
  double speed_mps = 1.0;         ///< > 0
  bool loop = false;
  double start_s = 0.0;
};

using MotionPath = std::variant<CirclePath, LinePath, WaypointPath>;

/// The position on the path at time t (seconds). Pure: no state, any t.
[[nodiscard]] Vec3 path_position(const MotionPath& path, double t);

/// The normal of a named plane: "xz" -> +y, "xy" -> +z, "yz" -> +x; none
/// for any other name.
[[nodiscard]] std::optional<Vec3> plane_normal(std::string_view plane);

}  // namespace earshot::scenes
