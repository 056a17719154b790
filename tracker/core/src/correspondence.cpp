#include "earshot/tracker/core/correspondence.hpp"

#include <cmath>

namespace earshot::tracker {

double rms_reprojection_error(const Pose& pose, std::span<const Correspondence> dots,
                              const Camera& cam, const LedModel& model) {
  if (dots.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& d : dots) {
    const Vec3 p = pose.apply(model.leds_mm[static_cast<size_t>(d.led)]);
    if (p.z() <= 1e-9) return INFINITY;  // behind the camera: no fit at all
    sum += (cam.project(p) - d.pixel).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(dots.size()));
}

}  // namespace earshot::tracker
