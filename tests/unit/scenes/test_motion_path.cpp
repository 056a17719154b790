// Motion paths: positions, speeds, periods and the Scene JSON "path" field.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/scenes/motion_path.hpp"
#include "earshot/scenes/scene.hpp"

using namespace earshot::scenes;
using earshot::Vec3;

namespace {

double dist(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}
void expect_near(const Vec3& got, const Vec3& want, double tol = 1e-9) {
  EXPECT_LT(dist(got, want), tol) << "got [" << got[0] << ", " << got[1] << ", " << got[2] << "] want [" << want[0]
                                  << ", " << want[1] << ", " << want[2] << "]";
}
std::string parse_error(const std::string& json) {
  try {
    (void)parse_scene(json, "s.json");
  } catch (const earshot::InputError& e) {
    return e.what();
  }
  return "";
}
/// The speed along a path at t, by a central difference.
double speed(const MotionPath& p, double t) {
  const double h = 1e-4;
  return dist(path_position(p, t + h), path_position(p, t - h)) / (2 * h);
}

}  // namespace

TEST(MotionPath, CircleInTheHorizontalPlaneGoesRightAheadLeftBehind) {
  CirclePath c;
  c.centre = {0, 1, 0};
  c.radius = 2;
  c.normal = *plane_normal("xz");
  c.period_s = 8;
  expect_near(path_position(c, 0), {2, 1, 0});
  expect_near(path_position(c, 2), {0, 1, -2});  // ahead is -z
  expect_near(path_position(c, 4), {-2, 1, 0});
  expect_near(path_position(c, 6), {0, 1, 2});
  expect_near(path_position(c, 8 + 1.3), path_position(c, 1.3), 1e-9);  // periodic
  c.clockwise = true;
  expect_near(path_position(c, 2), {0, 1, 2});  // clockwise seen from above: behind first
  c.phase_deg = 90;
  expect_near(path_position(c, 0), {0, 1, -2});
  for (double t = 0.1; t < 8; t += 0.37) {  // (at 0 the difference reaches before the start)
    EXPECT_NEAR(dist(path_position(c, t), c.centre), 2.0, 1e-12);
    EXPECT_NEAR(path_position(c, t)[1], 1.0, 1e-12);  // stays in its plane
    EXPECT_NEAR(speed(c, t), 2 * std::numbers::pi * 2 / 8, 1e-6);
  }
}

TEST(MotionPath, CircleInTheFrontalAndMedianPlanes) {
  CirclePath c;
  c.radius = 1;
  c.period_s = 4;
  c.normal = *plane_normal("xy");
  expect_near(path_position(c, 0), {1, 0, 0});
  expect_near(path_position(c, 1), {0, 1, 0});  // overhead
  c.normal = *plane_normal("yz");
  expect_near(path_position(c, 0), {0, 0, -1});  // ahead
  expect_near(path_position(c, 1), {0, 1, 0});
  expect_near(path_position(c, 2), {0, 0, 1});
  EXPECT_FALSE(plane_normal("xx").has_value());
  // Any normal: the circle lies in the plane through the centre perpendicular to it.
  c.normal = {1, 1, 1};
  c.start_s = 3;
  expect_near(path_position(c, 0), path_position(c, 3));  // holds its start until start_s
  for (double t = 3; t < 8; t += 0.41) {
    const Vec3 p = path_position(c, t);
    EXPECT_NEAR(p[0] + p[1] + p[2], 0.0, 1e-12);
    EXPECT_NEAR(dist(p, {0, 0, 0}), 1.0, 1e-12);
  }
}

TEST(MotionPath, LineOnceLoopAndPingPong) {
  LinePath l;
  l.from = {-10, 0, -5};
  l.to = {10, 0, -5};
  l.speed_mps = 4;  // 20 m in 5 s
  l.start_s = 1;
  expect_near(path_position(l, 0), l.from);
  expect_near(path_position(l, 1 + 2.5), {0, 0, -5});
  expect_near(path_position(l, 1 + 7), l.to);  // once: stays at the end
  EXPECT_NEAR(speed(l, 3), 4.0, 1e-6);
  l.mode = LinePath::Mode::loop;
  expect_near(path_position(l, 1 + 5 + 1), {-6, 0, -5}, 1e-9);
  l.mode = LinePath::Mode::ping_pong;
  expect_near(path_position(l, 1 + 5 + 1), {6, 0, -5}, 1e-9);  // on its way back
  expect_near(path_position(l, 1 + 10), l.from, 1e-9);
  EXPECT_NEAR(speed(l, 1 + 6), 4.0, 1e-6);
}

TEST(MotionPath, WaypointsAtConstantSpeed) {
  WaypointPath w;
  w.points = {{0, 0, 0}, {3, 0, 0}, {3, 4, 0}};  // 3 m then 4 m; back to the start 5 m
  w.speed_mps = 2;
  expect_near(path_position(w, 1), {2, 0, 0});
  expect_near(path_position(w, 2.5), {3, 2, 0});
  expect_near(path_position(w, 100), {3, 4, 0});  // not looping: stays at the last point
  w.loop = true;
  expect_near(path_position(w, 3.5 + 2.5 / 2), {1.5, 2, 0}, 1e-9);  // halfway home
  expect_near(path_position(w, 6 + 1), {2, 0, 0}, 1e-9);            // round again (12 m at 2 m/s)
  for (double t = 0.1; t < 12; t += 0.53) EXPECT_NEAR(speed(w, t), 2.0, 1e-6) << t;
}

TEST(MotionPath, SceneJsonPathReplacesPosition) {
  const Scene s = parse_scene(R"({"sources": [
      {"signal": {"type": "noise"}, "path": {"type": "circle", "radius": 2, "plane": "xy", "speed_mps": 1,
                                             "direction": "cw", "phase_deg": 90}},
      {"signal": {"type": "noise"}, "path": {"type": "line", "from": [0,0,0], "to": [1,0,0], "mode": "ping-pong"}},
      {"signal": {"type": "noise"}, "path": {"type": "waypoints", "points": [[0,0,0],[0,1,0]], "loop": true}},
      {"signal": {"type": "noise"}, "position": [1, 2, 3]}]})", "s.json");
  ASSERT_EQ(s.sources.size(), 4u);
  ASSERT_TRUE(s.sources[0].path.has_value());
  const auto& c = std::get<CirclePath>(*s.sources[0].path);
  EXPECT_NEAR(c.period_s, 4 * std::numbers::pi, 1e-12);  // 2 pi r / speed
  EXPECT_TRUE(c.clockwise);
  expect_near(source_position(s.sources[0], 0), {0, 2, 0});
  expect_near(s.sources[0].position, {0, 2, 0});  // the start, for anything that wants one point
  EXPECT_EQ(std::get<LinePath>(*s.sources[1].path).mode, LinePath::Mode::ping_pong);
  EXPECT_TRUE(std::get<WaypointPath>(*s.sources[2].path).loop);
  EXPECT_FALSE(s.sources[3].path.has_value());
  expect_near(source_position(s.sources[3], 5), {1, 2, 3});
}

TEST(MotionPath, BadPathsNameTheField) {
  auto src = [](const std::string& path) {
    return R"({"sources": [{"signal": {"type": "noise"}, "path": )" + path + "}]}";
  };
  EXPECT_EQ(parse_error(src(R"({"type": "spiral"})")),
            "s.json: field 'sources[0].path.type': unknown type 'spiral' (circle, line, waypoints)");
  EXPECT_EQ(parse_error(src(R"({"type": "circle"})")),
            "s.json: field 'sources[0].path.radius': missing: the circle's radius in metres");
  EXPECT_EQ(parse_error(src(R"({"type": "circle", "radius": 1, "plane": "ab"})")),
            "s.json: field 'sources[0].path.plane': unknown plane 'ab' (xz, xy, yz)");
  EXPECT_EQ(parse_error(src(R"({"type": "circle", "radius": 1, "normal": [0, 0, 0]})")),
            "s.json: field 'sources[0].path.normal': must not be zero");
  EXPECT_EQ(parse_error(src(R"({"type": "circle", "radius": 1, "period_s": 2, "speed_mps": 1})")),
            "s.json: field 'sources[0].path.speed_mps': give period_s or speed_mps, not both");
  EXPECT_EQ(parse_error(src(R"({"type": "circle", "radius": 1, "direction": "up"})")),
            "s.json: field 'sources[0].path.direction': unknown direction 'up' (ccw, cw)");
  EXPECT_EQ(parse_error(src(R"({"type": "line", "from": [0,0,0], "to": [1,0,0], "speed_mps": 400})")),
            "s.json: field 'sources[0].path.speed_mps': out of range: 400 (allowed 0.001 to 300)");
  EXPECT_EQ(parse_error(src(R"({"type": "line", "from": [0,0,0]})")),
            "s.json: field 'sources[0].path.to': missing: the line's end, [x, y, z]");
  EXPECT_EQ(parse_error(src(R"({"type": "waypoints", "points": [[0,0,0]]})")),
            "s.json: field 'sources[0].path.points': expected 2 to 10000 points [[x, y, z], ...]");
  EXPECT_EQ(parse_error(src(R"({"type": "waypoints", "points": [[0,0,0], [1, "a", 0]]})")),
            "s.json: field 'sources[0].path.points[1]': expected [x, y, z] in metres (finite, within 100 km)");
  EXPECT_EQ(parse_error(src(R"({"type": "line", "from": [0,0,0], "to": [1,0,0], "speed": 1})")),
            "s.json: field 'sources[0].path.speed': unknown field");
  EXPECT_EQ(parse_error(R"({"sources": [{"signal": {"type": "noise"}, "position": [0,0,-1],
                           "path": {"type": "line", "from": [0,0,0], "to": [1,0,0]}}]})"),
            "s.json: field 'sources[0].path': a source has a position or a path, not both");
}
