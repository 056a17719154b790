// OpenAL's distance models (OpenAL 1.1 specification, section 3.4): the gain
// of a source at distance d from the listener.
#pragma once

#include <limits>
#include <optional>
#include <string_view>

namespace earshot::audio {

enum class DistanceModel {
  none,
  inverse, inverse_clamped,
  linear, linear_clamped,
  exponent, exponent_clamped,
};

[[nodiscard]] std::optional<DistanceModel> distance_model_from(std::string_view name);

struct DistanceParams {
  DistanceModel model = DistanceModel::inverse_clamped;  ///< OpenAL's default
  double reference_distance = 1.0;
  double rolloff = 1.0;
  double max_distance = std::numeric_limits<double>::max();
};

/// Gain in [0, inf) (>= 0; above 1 only inside the reference distance of an
/// unclamped model, as in OpenAL).
[[nodiscard]] double distance_gain(double distance, const DistanceParams& p);

}  // namespace earshot::audio
