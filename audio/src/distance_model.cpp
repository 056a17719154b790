#include "earshot/audio/distance_model.hpp"

#include <algorithm>
#include <cmath>

namespace earshot::audio {

std::optional<DistanceModel> distance_model_from(std::string_view n) {
  if (n == "none") return DistanceModel::none;
  if (n == "inverse") return DistanceModel::inverse;
  if (n == "inverse-clamped") return DistanceModel::inverse_clamped;
  if (n == "linear") return DistanceModel::linear;
  if (n == "linear-clamped") return DistanceModel::linear_clamped;
  if (n == "exponent") return DistanceModel::exponent;
  if (n == "exponent-clamped") return DistanceModel::exponent_clamped;
  return std::nullopt;
}

double distance_gain(double d, const DistanceParams& p) {
  const double ref = p.reference_distance, roll = p.rolloff, maxd = p.max_distance;
  const bool clamped = p.model == DistanceModel::inverse_clamped || p.model == DistanceModel::linear_clamped ||
                       p.model == DistanceModel::exponent_clamped;
  if (clamped) d = std::clamp(d, ref, std::max(ref, maxd));
  double g = 1.0;
  switch (p.model) {
    case DistanceModel::none: return 1.0;
    case DistanceModel::inverse:
    case DistanceModel::inverse_clamped: {
      const double den = ref + roll * (d - ref);
      g = den > 0.0 ? ref / den : 1.0;
      break;
    }
    case DistanceModel::linear:
    case DistanceModel::linear_clamped: {
      const double span = maxd - ref;
      g = span > 0.0 ? 1.0 - roll * (std::min(d, maxd) - ref) / span : 1.0;
      break;
    }
    case DistanceModel::exponent:
    case DistanceModel::exponent_clamped:
      g = (d > 0.0 && ref > 0.0) ? std::pow(d / ref, -roll) : 1.0;
      break;
  }
  return std::isfinite(g) ? std::max(0.0, g) : 0.0;
}

}  // namespace earshot::audio
