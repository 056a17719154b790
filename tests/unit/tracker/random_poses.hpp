// Random poses and frames for the tracker tests (seeded, reproducible).
#pragma once

#include <cmath>
#include <random>

#include "earshot/tracker/core/camera.hpp"
#include "earshot/tracker/core/correspondence.hpp"
#include "earshot/tracker/core/dots_csv.hpp"
#include "earshot/tracker/core/led_model.hpp"

namespace earshot::tracker::fixtures {

/// A random beacon pose in front of the camera with every LED inside the
/// image and shining toward the camera within its beam half-angle (a real
/// camera sees nothing else): any roll (full circle), yaw and pitch within
/// +-40 degrees.
inline Pose random_visible_pose(std::mt19937_64& rng, const Camera& cam, const LedModel& model) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (;;) {
    const double yaw = 0.7 * u(rng), pitch = 0.7 * u(rng), roll = M_PI * u(rng);
    const double z = 900.0 + 600.0 * u(rng);
    // Draws are sequenced one per statement: the order of function arguments
    // is unspecified (g++ and clang differ), and the poses must not be.
    const double x = 0.25 * z * u(rng);
    const double y = 0.2 * z * u(rng);
    const Pose p{rotation_from_ypr(yaw, pitch, roll), Vec3(x, y, z)};
    bool ok = true;
    const Vec3 axis = p.R * model.axis;
    for (const auto& led : model.leds_mm) {
      const Vec3 P = p.apply(led);
      ok = ok && cam.inside(cam.project(P)) && axis.dot(-P.normalized()) >= std::cos(model.half_angle);
    }
    if (ok) return p;
  }
}

/// The four labelled, noise-free dots of a pose.
inline LabelledDots exact_dots(const Pose& p, const Camera& cam, const LedModel& model) {
  LabelledDots d;
  for (int l = 0; l < 4; ++l) d.add(l, cam.project(p.apply(model.leds_mm[static_cast<size_t>(l)])));
  return d;
}

/// A frame with the dots of `p`, LED `order[s]` in slot s (-1 = empty slot).
inline DotFrame frame_of(const Pose& p, const Camera& cam, const LedModel& model,
                         const std::array<int, 4>& order, double t = 0.0) {
  DotFrame f;
  f.t = t;
  for (size_t s = 0; s < 4; ++s)
    if (order[s] >= 0) f.slots[s] = cam.project(p.apply(model.leds_mm[static_cast<size_t>(order[s])]));
  return f;
}

}  // namespace earshot::tracker::fixtures
