#include "earshot/scenes/motion_path.hpp"

#include <cmath>
#include <numbers>

namespace earshot::scenes {
namespace {

Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 scale(const Vec3& a, double k) { return {a[0] * k, a[1] * k, a[2] * k}; }
Vec3 unit(const Vec3& a) { return scale(a, 1.0 / std::sqrt(dot(a, a))); }
Vec3 lerp(const Vec3& a, const Vec3& b, double f) { return add(a, scale(sub(b, a), f)); }

Vec3 at(const CirclePath& c, double t) {
  const Vec3 n = unit(c.normal);
  // +x projected into the plane; -z when the normal is (nearly) x itself.
  const Vec3 a = std::abs(n[0]) > 0.9 ? Vec3{0, 0, -1} : Vec3{1, 0, 0};
  const Vec3 u = unit(sub(a, scale(n, dot(a, n))));
  const Vec3 v = cross(n, u);
  const double turns = std::max(0.0, t - c.start_s) / c.period_s;
  const double ang = c.phase_deg * std::numbers::pi / 180.0 +
                     (c.clockwise ? -1.0 : 1.0) * 2.0 * std::numbers::pi * (turns - std::floor(turns));
  return add(c.centre, scale(add(scale(u, std::cos(ang)), scale(v, std::sin(ang))), c.radius));
}

Vec3 at(const LinePath& l, double t) {
  const double len = std::sqrt(dot(sub(l.to, l.from), sub(l.to, l.from)));
  if (len <= 0.0) return l.from;
  const double s = std::max(0.0, t - l.start_s) * l.speed_mps;  // distance travelled
  double f = 0.0;
  switch (l.mode) {
    case LinePath::Mode::once: f = std::min(1.0, s / len); break;
    case LinePath::Mode::loop: f = std::fmod(s, len) / len; break;
    case LinePath::Mode::ping_pong: {
      const double r = std::fmod(s, 2.0 * len);
      f = (r <= len ? r : 2.0 * len - r) / len;
      break;
    }
  }
  return lerp(l.from, l.to, f);
}

Vec3 at(const WaypointPath& w, double t) {
  const std::size_t n = w.points.size();
  if (n == 0) return {0, 0, 0};
  if (n == 1) return w.points[0];
  const std::size_t segs = w.loop ? n : n - 1;
  double total = 0.0;
  for (std::size_t i = 0; i < segs; ++i) {
    const Vec3 d = sub(w.points[(i + 1) % n], w.points[i]);
    total += std::sqrt(dot(d, d));
  }
  if (total <= 0.0) return w.points[0];
  double s = std::max(0.0, t - w.start_s) * w.speed_mps;
  if (w.loop)
    s = std::fmod(s, total);
  else if (s >= total)
    return w.points[n - 1];
  for (std::size_t i = 0; i < segs; ++i) {
    const Vec3 &a = w.points[i], &b = w.points[(i + 1) % n];
    const double len = std::sqrt(dot(sub(b, a), sub(b, a)));
    if (s <= len) return len > 0.0 ? lerp(a, b, s / len) : a;
    s -= len;
  }
  return w.points[w.loop ? 0 : n - 1];  // rounding at the very end
}

}  // namespace

Vec3 path_position(const MotionPath& path, double t) {
  return std::visit([t](const auto& p) { return at(p, t); }, path);
}

std::optional<Vec3> plane_normal(std::string_view plane) {
  if (plane == "xz") return Vec3{0, 1, 0};
  if (plane == "xy") return Vec3{0, 0, 1};
  if (plane == "yz") return Vec3{1, 0, 0};
  return std::nullopt;
}

}  // namespace earshot::scenes
