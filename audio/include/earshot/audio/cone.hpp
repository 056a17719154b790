// A directional source's cone, OpenAL's (1.1 specification, section 3.4.3):
// full gain inside the inner cone, outer_gain outside the outer cone, and a
// linear blend between, by the angle between the source's direction and the
// line from the source to the listener. A zero direction is omnidirectional.
#pragma once

#include <array>

namespace earshot::audio {

struct ConeParams {
  std::array<double, 3> direction{0, 0, 0};  ///< where the source points; zero: everywhere
  double inner_angle_deg = 360.0;            ///< full angle of the inner cone
  double outer_angle_deg = 360.0;            ///< full angle of the outer cone
  double outer_gain = 0.0;                   ///< gain outside the outer cone
};

/// Gain for a listener seen from the source along `to_listener`.
[[nodiscard]] double cone_gain(const std::array<double, 3>& to_listener, const ConeParams& cone);

}  // namespace earshot::audio
