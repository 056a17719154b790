#include "earshot/tracker/core/led_model.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "earshot/errors.hpp"

namespace earshot::tracker {
namespace {

using nlohmann::json;

Vec3 read_vec3(const json& j, std::string_view origin, const std::string& field) {
  if (!j.is_array() || j.size() != 3) throw InputError::at(origin, 0, field, "expected [x, y, z]");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    const auto& e = j[static_cast<size_t>(i)];
    if (!e.is_number()) throw InputError::at(origin, 0, field, "expected a number, got " + e.dump());
    v[i] = e.get<double>();
    if (!std::isfinite(v[i])) throw InputError::at(origin, 0, field, "not a finite number");
  }
  return v;
}

}  // namespace

LedModel parse_led_model(std::string_view json_text, std::string_view origin) {
  json j;
  try {
    j = json::parse(json_text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number overflow
    throw InputError::at(origin, 0, "", std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) throw InputError::at(origin, 0, "", "expected a JSON object");
  LedModel m;
  for (const auto& [key, value] : j.items()) {
    if (key == "leds_mm") {
      if (!value.is_array() || value.size() != 4)
        throw InputError::at(origin, 0, "leds_mm", "expected four [x, y, z] points");
      for (size_t i = 0; i < 4; ++i)
        m.leds_mm[i] = read_vec3(value[i], origin, "leds_mm[" + std::to_string(i) + "]");
    } else if (key == "axis") {
      m.axis = read_vec3(value, origin, "axis");
      if (m.axis.norm() < 1e-9) throw InputError::at(origin, 0, "axis", "must not be zero");
      m.axis.normalize();
    } else if (key == "half_angle_deg") {
      if (!value.is_number()) throw InputError::at(origin, 0, key, "expected a number");
      const double a = value.get<double>();
      if (!(a > 0.0 && a <= 90.0)) throw InputError::at(origin, 0, key, "must be in (0, 90]");
      m.half_angle = a * std::numbers::pi / 180.0;
    } else {
      throw InputError::at(origin, 0, key, "unknown field");
    }
  }
  if (!j.contains("leds_mm")) throw InputError::at(origin, 0, "leds_mm", "missing");
  // Four LEDs in one plane or on one line give no unique pose from three.
  const Vec3 a = m.leds_mm[1] - m.leds_mm[0], b = m.leds_mm[2] - m.leds_mm[0];
  if (a.cross(b).norm() < 1e-6 * a.norm() * b.norm())
    throw InputError::at(origin, 0, "leds_mm", "the first three LEDs are collinear");
  for (size_t i = 0; i < 4; ++i)
    for (size_t k = i + 1; k < 4; ++k)
      if ((m.leds_mm[i] - m.leds_mm[k]).norm() < 1.0)
        throw InputError::at(origin, 0, "leds_mm", "two LEDs closer than 1 mm");
  return m;
}

LedModel load_led_model(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError::at(path.string(), 0, "", "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_led_model(ss.str(), path.string());
}

}  // namespace earshot::tracker
