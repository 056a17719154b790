#include "earshot/audio/cone.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace earshot::audio {

double cone_gain(const std::array<double, 3>& to_listener, const ConeParams& cone) {
  const auto& d = cone.direction;
  const double dn = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  const double ln = std::sqrt(to_listener[0] * to_listener[0] + to_listener[1] * to_listener[1] +
                              to_listener[2] * to_listener[2]);
  if (!(dn > 0.0) || !(ln > 0.0) || !std::isfinite(dn) || !std::isfinite(ln)) return 1.0;
  const double cosine = (d[0] * to_listener[0] + d[1] * to_listener[1] + d[2] * to_listener[2]) / (dn * ln);
  const double angle = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / std::numbers::pi;
  const double inner = std::clamp(cone.inner_angle_deg, 0.0, 360.0) / 2.0;
  const double outer = std::max(inner, std::clamp(cone.outer_angle_deg, 0.0, 360.0) / 2.0);
  const double outer_gain = std::clamp(cone.outer_gain, 0.0, 1.0);
  if (angle <= inner) return 1.0;
  if (angle >= outer) return outer_gain;
  return 1.0 + (outer_gain - 1.0) * (angle - inner) / (outer - inner);
}

}  // namespace earshot::audio
