// The beacon: four IR LEDs at known positions on the headphones (model frame, mm).
#pragma once

#include <array>
#include <filesystem>
#include <string_view>

#include "earshot/tracker/core/geometry.hpp"

namespace earshot::tracker {

struct LedModel {
  /// LED positions in mm, model frame. Default: the thesis beacon (fig. 41).
  std::array<Vec3, 4> leds_mm{Vec3(63.5, 13.5, 3.0), Vec3(-63.5, 16.5, 3.0),
                              Vec3(64.5, -66.0, 3.0), Vec3(-64.5, -16.5, 24.0)};
  /// Direction the LEDs shine in, model frame. At the identity pose the beacon
  /// faces the camera, so the LEDs shine along the camera's -z.
  Vec3 axis{0.0, 0.0, -1.0};
  /// Beam half-angle (radians): beyond it the camera no longer sees the LED.
  /// 45 degrees for the thesis's OP165W.
  double half_angle = 0.7853981633974483;

  [[nodiscard]] static LedModel thesis() { return {}; }
};

/// Reads a Model JSON file: {"leds_mm": [[x,y,z] x4], optional "axis": [x,y,z],
/// optional "half_angle_deg": a}. Throws InputError naming the file and field.
[[nodiscard]] LedModel load_led_model(const std::filesystem::path& path);

/// Same, from JSON text; `origin` names the source in error messages.
[[nodiscard]] LedModel parse_led_model(std::string_view json_text, std::string_view origin);

}  // namespace earshot::tracker
