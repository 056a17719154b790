#include "earshot/scenes/scene.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "earshot/audio/room_presets.hpp"
#include "earshot/errors.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace earshot::scenes {
namespace {

using nlohmann::json;

/// Reads fields of one JSON object, refusing unknown ones.
class Fields {
 public:
  Fields(const json& j, std::string_view origin, std::string path)
      : j_(j), origin_(origin), path_(std::move(path)) {
    if (!j_.is_object()) fail("", "expected an object");
  }
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    std::string f = path_;
    if (!field.empty()) f += (f.empty() ? "" : ".") + field;
    throw InputError::at(origin_, 0, f, what);
  }
  bool has(const char* k) {
    seen_.insert(k);
    return j_.contains(k);
  }
  const json& at(const char* k) { return seen_.insert(k), j_.at(k); }
  double number(const char* k, double def, double lo, double hi) {
    if (!has(k)) return def;
    const json& v = j_.at(k);
    if (!v.is_number()) fail(k, "expected a number, got " + v.dump());
    const double x = v.get<double>();
    if (!std::isfinite(x) || x < lo || x > hi)
      fail(k, "out of range: " + v.dump() + " (allowed " + num(lo) + " to " + num(hi) + ")");
    return x;
  }
  std::string text(const char* k, const std::string& def) {
    if (!has(k)) return def;
    const json& v = j_.at(k);
    if (!v.is_string()) fail(k, "expected a string, got " + v.dump());
    return v.get<std::string>();
  }
  std::array<double, 3> vec3(const char* k, std::array<double, 3> def) {
    if (!has(k)) return def;
    const json& v = j_.at(k);
    if (!v.is_array() || v.size() != 3) fail(k, "expected [x, y, z] in metres");
    std::array<double, 3> out{};
    for (std::size_t i = 0; i < 3; ++i) {
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>()) || std::abs(v[i].get<double>()) > 1e5)
        fail(k, "expected [x, y, z] in metres (finite, within 100 km)");
      out[i] = v[i].get<double>();
    }
    return out;
  }
  void done() const {
    for (const auto& [key, value] : j_.items())
      if (!seen_.count(key)) fail(key, "unknown field");
  }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  static std::string num(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  const json& j_;
  std::string_view origin_;
  std::string path_;
  std::set<std::string> seen_;
};

std::filesystem::path resolve(const std::filesystem::path& base, const std::string& p) {
  const std::filesystem::path path(p);
  return path.is_relative() && !base.empty() ? base / path : path;
}

Signal parse_signal(const json& j, std::string_view origin, const std::string& where, const std::filesystem::path& base) {
  Fields f(j, origin, where);
  Signal s;
  const std::string type = f.text("type", "");
  if (type == "noise") {
    s.type = Signal::Type::noise;
    s.seed = static_cast<std::uint64_t>(f.number("seed", 1, 0, 9.007199254740992e15));
  } else if (type == "sine") {
    s.type = Signal::Type::sine;
    s.frequency_hz = f.number("frequency_hz", 440, 0.0, 96000.0);
  } else if (type == "impulse") {
    s.type = Signal::Type::impulse;
  } else if (type == "file") {
    s.type = Signal::Type::file;
    const std::string p = f.text("path", "");
    if (p.empty()) f.fail("path", "missing: the audio file to play");
    s.path = resolve(base, p);
  } else {
    f.fail("type", type.empty() ? "missing (noise, sine, impulse, file)"
                                : "unknown signal type '" + type + "' (noise, sine, impulse, file)");
  }
  f.done();
  return s;
}

}  // namespace

Scene parse_scene(std::string_view text, std::string_view origin, const std::filesystem::path& base) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw InputError::at(origin, 0, "", std::string("not valid JSON: ") + e.what());
  }
  Fields f(j, origin, "");
  Scene s;
  s.duration_s = f.number("duration_s", 5.0, 0.0, 3600.0);
  s.sample_rate = f.number("sample_rate", 48000.0, 8000.0, 192000.0);
  s.room = f.text("room", "none");
  if (s.room != "none") {
    try {
      (void)audio::room_preset(s.room);
    } catch (const InputError&) {
      f.fail("room", "unknown room preset '" + s.room + "' (available: none, " + audio::room_preset_names() + ")");
    }
  }
  s.reverb = f.text("reverb", "fdn");
  if (s.reverb != "fdn" && s.reverb != "schroeder")
    f.fail("reverb", "unknown reverb '" + s.reverb + "' (available: fdn, schroeder)");
  s.doppler_factor = f.number("doppler_factor", 1.0, 0.0, 10.0);
  s.speed_of_sound = f.number("speed_of_sound", 343.3, 1.0, 10000.0);
  if (f.has("listener")) {
    Fields l(f.at("listener"), origin, "listener");
    if (l.has("head_size")) {
      const json& h = l.at("head_size");
      if (h.is_number()) {
        const double r = h.get<double>();
        if (!(r >= 0.05 && r <= 0.15)) l.fail("head_size", "radius out of range: " + h.dump() + " (0.05 to 0.15 m)");
        s.listener.head_radius_m = r;
      } else if (h == "small") {
        s.listener.head_radius_m = hrtf::head_radius_m(hrtf::HeadSize::small);
      } else if (h == "medium") {
        s.listener.head_radius_m = hrtf::head_radius_m(hrtf::HeadSize::medium);
      } else if (h == "large") {
        s.listener.head_radius_m = hrtf::head_radius_m(hrtf::HeadSize::large);
      } else if (h != "measured") {
        l.fail("head_size", "expected measured, small, medium, large or a radius in metres, got " + h.dump());
      }
    }
    s.listener.position = l.vec3("position", {0, 0, 0});
    s.listener.yaw_deg = l.number("yaw_deg", 0, -360, 360);
    s.listener.pitch_deg = l.number("pitch_deg", 0, -90, 90);
    s.listener.roll_deg = l.number("roll_deg", 0, -360, 360);
    l.done();
  }
  if (f.has("pose_track")) s.pose_track = resolve(base, f.text("pose_track", ""));
  if (!f.has("sources") || !f.at("sources").is_array()) f.fail("sources", "expected an array of sources");
  const json& arr = f.at("sources");
  for (std::size_t i = 0; i < arr.size(); ++i) {
    const std::string where = "sources[" + std::to_string(i) + "]";
    Fields sf(arr[i], origin, where);
    SceneSource src;
    src.name = sf.text("name", "source " + std::to_string(i + 1));
    if (!sf.has("signal")) sf.fail("signal", "missing");
    src.signal = parse_signal(sf.at("signal"), origin, where + ".signal", base);
    src.position = sf.vec3("position", {0, 0, -1});
    src.gain_db = sf.number("gain_db", 0, -120, 40);
    const std::string model = sf.text("distance_model", "inverse-clamped");
    const auto m = audio::distance_model_from(model);
    if (!m) sf.fail("distance_model", "unknown model '" + model + "' (none, inverse, inverse-clamped, linear, "
                                      "linear-clamped, exponent, exponent-clamped)");
    src.distance.model = *m;
    src.distance.reference_distance = sf.number("reference_distance", 1, 1e-3, 1e5);
    src.distance.rolloff = sf.number("rolloff", 1, 0, 100);
    src.distance.max_distance = sf.number("max_distance", 1e5, 1e-3, 1e5);
    src.reverb_send_db = sf.number("reverb_send_db", -120, -120, 20);
    src.air_absorption = sf.number("air_absorption", 0, 0, 10);
    sf.done();
    s.sources.push_back(src);
  }
  f.done();
  return s;
}

Scene load_scene(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError::at(path.string(), 0, "", "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), path.string(), path.parent_path());
}

}  // namespace earshot::scenes
