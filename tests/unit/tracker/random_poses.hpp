// Random poses and frames for the tracker tests (seeded, reproducible).
#pragma once

#include <random>

#include "earshot/tracker/camera.hpp"
#include "earshot/tracker/correspondence.hpp"
#include "earshot/tracker/dots_csv.hpp"
#include "earshot/tracker/led_model.hpp"

namespace earshot::tracker::fixtures {

/// A random beacon pose in front of the camera with every LED inside the
/// image: any roll (full circle), yaw and pitch within +-40 degrees.
inline Pose random_visible_pose(std::mt19937_64& rng, const Camera& cam, const LedModel& model) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (;;) {
    const double yaw = 0.7 * u(rng), pitch = 0.7 * u(rng), roll = M_PI * u(rng);
    const double z = 900.0 + 600.0 * u(rng);
    const Pose p{rotation_from_ypr(yaw, pitch, roll), Vec3(0.25 * z * u(rng), 0.2 * z * u(rng), z)};
    bool ok = true;
    for (const auto& led : model.leds_mm) ok = ok && cam.inside(cam.project(p.apply(led)));
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
