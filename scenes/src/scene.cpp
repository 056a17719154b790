#include "earshot/scenes/scene.hpp"

#include <cmath>
#include <initializer_list>
#include <numbers>
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
    return point(j_.at(k), k);
  }
  /// A value that must be [x, y, z]; `field` names it in errors.
  std::array<double, 3> point(const json& v, const std::string& field) const {
    if (!v.is_array() || v.size() != 3) fail(field, "expected [x, y, z] in metres");
    std::array<double, 3> out{};
    for (std::size_t i = 0; i < 3; ++i) {
      if (!v[i].is_number() || !std::isfinite(v[i].get<double>()) || std::abs(v[i].get<double>()) > 1e5)
        fail(field, "expected [x, y, z] in metres (finite, within 100 km)");
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

constexpr const char* kSignalTypes =
    "noise, sine, impulse, file, voice, talk, siren, birds, engine, horn, footsteps, ambience, animal";

std::uint64_t seed(Fields& f) { return static_cast<std::uint64_t>(f.number("seed", 1, 0, 9.007199254740992e15)); }

/// A string field that must be one of `names` ("a, b, c"); returns its index.
std::size_t choice(Fields& f, const char* k, std::initializer_list<const char*> names, const char* def) {
  const std::string v = f.text(k, def);
  std::string all;
  std::size_t i = 0;
  for (const char* n : names) {
    if (v == n) return i;
    all += (i++ ? ", " : "") + std::string(n);
  }
  f.fail(k, v.empty() ? "missing (" + all + ")" : "unknown " + std::string(k) + " '" + v + "' (" + all + ")");
}

bool boolean(Fields& f, const char* k, bool def) {
  if (!f.has(k)) return def;
  const json& v = f.at(k);
  if (!v.is_boolean()) f.fail(k, "expected true or false, got " + v.dump());
  return v.get<bool>();
}

Signal parse_signal(const json& j, std::string_view origin, const std::string& where, const std::filesystem::path& base) {
  Fields f(j, origin, where);
  Signal s;
  using T = Signal::Type;
  const std::string type = f.text("type", "");
  constexpr double kMaxHz = 20000.0;
  if (type == "noise") {
    s.type = T::noise;
    s.seed = seed(f);
  } else if (type == "sine") {
    s.type = T::sine;
    s.frequency_hz = f.number("frequency_hz", 440, 0.0, 96000.0);
  } else if (type == "impulse") {
    s.type = T::impulse;
  } else if (type == "file") {
    s.type = T::file;
    const std::string p = f.text("path", "");
    if (p.empty()) f.fail("path", "missing: the audio file to play");
    s.path = resolve(base, p);
    s.loop = boolean(f, "loop", false);
  } else if (type == "voice") {
    s.type = T::voice;
    auto& v = s.voice;
    v.pitch_hz = f.number("pitch_hz", v.pitch_hz, 50, 2000);
    if (f.has("melody")) {
      const json& m = f.at("melody");
      if (!m.is_array() || m.empty() || m.size() > 1000) f.fail("melody", "expected 1 to 1000 semitone offsets");
      v.melody.clear();
      for (const json& x : m) {
        if (!x.is_number() || std::abs(x.get<double>()) > 36)
          f.fail("melody", "expected semitones within +-36, got " + x.dump());
        v.melody.push_back(x.get<double>());
      }
    }
    v.note_s = f.number("note_s", v.note_s, 0.05, 10);
    v.vowels = f.text("vowels", v.vowels);
    if (v.vowels.empty() || v.vowels.find_first_not_of("aeiou") != std::string::npos)
      f.fail("vowels", "expected letters from a, e, i, o, u, got \"" + v.vowels + "\"");
    v.vibrato_hz = f.number("vibrato_hz", v.vibrato_hz, 0, 20);
    v.vibrato_cents = f.number("vibrato_cents", v.vibrato_cents, 0, 200);
    v.formant_shift = f.number("formant_shift", v.formant_shift, 0.5, 2);
  } else if (type == "talk") {
    s.type = T::talk;
    s.seed = seed(f);
    s.talk.pitch_hz = f.number("pitch_hz", s.talk.pitch_hz, 50, 500);
    s.talk.syllables_per_s = f.number("syllables_per_s", s.talk.syllables_per_s, 0.5, 12);
    s.talk.formant_shift = f.number("formant_shift", s.talk.formant_shift, 0.5, 2);
  } else if (type == "siren") {
    s.type = T::siren;
    s.siren.mode = static_cast<SirenParams::Mode>(choice(f, "mode", {"wail", "yelp"}, "wail"));
    s.siren.low_hz = f.number("low_hz", s.siren.low_hz, 50, kMaxHz);
    s.siren.high_hz = f.number("high_hz", s.siren.high_hz, 50, kMaxHz);
    if (s.siren.high_hz < s.siren.low_hz) f.fail("high_hz", "below low_hz");
    s.siren.period_s = f.number("period_s", 0.0, 0.0, 60);
  } else if (type == "birds") {
    s.type = T::birds;
    s.seed = seed(f);
    s.birds.chirps_per_s = f.number("chirps_per_s", s.birds.chirps_per_s, 0.01, 50);
    s.birds.pitch_hz = f.number("pitch_hz", s.birds.pitch_hz, 200, 12000);
  } else if (type == "engine") {
    s.type = T::engine;
    s.seed = seed(f);
    s.engine.rpm = f.number("rpm", s.engine.rpm, 300, 12000);
    s.engine.cylinders = f.number("cylinders", s.engine.cylinders, 1, 16);
  } else if (type == "horn") {
    s.type = T::horn;
    s.horn.frequency_hz = f.number("frequency_hz", s.horn.frequency_hz, 50, 5000);
    s.horn.on_s = f.number("on_s", s.horn.on_s, 0.05, 60);
    s.horn.period_s = f.number("period_s", s.horn.period_s, 0.1, 3600);
    s.horn.start_s = f.number("start_s", s.horn.start_s, 0, 3600);
    s.horn.count = std::floor(f.number("count", 0, 0, 1e6));
  } else if (type == "footsteps") {
    s.type = T::footsteps;
    s.seed = seed(f);
    s.footsteps.steps_per_s = f.number("steps_per_s", s.footsteps.steps_per_s, 0.2, 10);
  } else if (type == "ambience") {
    s.type = T::ambience;
    s.seed = seed(f);
    s.ambience.kind = static_cast<AmbienceParams::Kind>(choice(f, "kind", {"city", "pink"}, "city"));
    s.ambience.hum_hz = f.number("hum_hz", s.ambience.hum_hz, 20, 400);
  } else if (type == "animal") {
    s.type = T::animal;
    s.seed = seed(f);
    s.animal.kind = static_cast<AnimalParams::Kind>(choice(f, "kind", {"lion", "elephant", "monkey", "parrot"}, ""));
    s.animal.interval_s = f.number("interval_s", 0.0, 0.0, 600);
    s.animal.pitch_scale = f.number("pitch_scale", 1.0, 0.25, 4);
  } else {
    f.fail("type", type.empty() ? std::string("missing (") + kSignalTypes + ")"
                                : "unknown signal type '" + type + "' (" + kSignalTypes + ")");
  }
  f.done();
  return s;
}

MotionPath parse_path(const json& j, std::string_view origin, const std::string& where) {
  Fields f(j, origin, where);
  const std::size_t type = choice(f, "type", {"circle", "line", "waypoints"}, "");
  constexpr double kMaxSpeed = 300.0;  // m/s: below the speed of sound, so Doppler stays defined
  MotionPath out;
  if (type == 0) {
    CirclePath c;
    c.centre = f.vec3("centre", c.centre);
    if (!f.has("radius")) f.fail("radius", "missing: the circle's radius in metres");
    c.radius = f.number("radius", 1, 0.01, 1e4);
    if (f.has("plane") && f.has("normal")) f.fail("normal", "give plane or normal, not both");
    if (f.has("normal")) {
      c.normal = f.vec3("normal", c.normal);
      if (c.normal[0] * c.normal[0] + c.normal[1] * c.normal[1] + c.normal[2] * c.normal[2] < 1e-12)
        f.fail("normal", "must not be zero");
    } else {
      const std::string plane = f.text("plane", "xz");
      const auto n = plane_normal(plane);
      if (!n) f.fail("plane", "unknown plane '" + plane + "' (xz, xy, yz)");
      c.normal = *n;
    }
    if (f.has("period_s") && f.has("speed_mps")) f.fail("speed_mps", "give period_s or speed_mps, not both");
    if (f.has("speed_mps"))
      c.period_s = 2.0 * std::numbers::pi * c.radius / f.number("speed_mps", 1, 0.001, kMaxSpeed);
    else
      c.period_s = f.number("period_s", c.period_s, 0.01, 1e5);
    c.phase_deg = f.number("phase_deg", 0, -360, 360);
    c.clockwise = choice(f, "direction", {"ccw", "cw"}, "ccw") == 1;
    c.start_s = f.number("start_s", 0, 0, 1e5);
    out = c;
  } else if (type == 1) {
    LinePath l;
    if (!f.has("from") || !f.has("to")) f.fail(f.has("from") ? "to" : "from", "missing: the line's end, [x, y, z]");
    l.from = f.vec3("from", l.from);
    l.to = f.vec3("to", l.to);
    l.speed_mps = f.number("speed_mps", l.speed_mps, 0.001, kMaxSpeed);
    l.mode = static_cast<LinePath::Mode>(choice(f, "mode", {"once", "loop", "ping-pong"}, "once"));
    l.start_s = f.number("start_s", 0, 0, 1e5);
    out = l;
  } else {
    WaypointPath w;
    if (!f.has("points") || !f.at("points").is_array() || f.at("points").size() < 2 || f.at("points").size() > 10000)
      f.fail("points", "expected 2 to 10000 points [[x, y, z], ...]");
    const json& pts = f.at("points");
    for (std::size_t i = 0; i < pts.size(); ++i) w.points.push_back(f.point(pts[i], "points[" + std::to_string(i) + "]"));
    w.speed_mps = f.number("speed_mps", w.speed_mps, 0.001, kMaxSpeed);
    w.loop = boolean(f, "loop", false);
    w.start_s = f.number("start_s", 0, 0, 1e5);
    out = w;
  }
  f.done();
  return out;
}

/// "listener": the head's size and the listener's pose in the room.
SceneListener parse_listener(const json& j, std::string_view origin) {
  Fields l(j, origin, "listener");
  SceneListener out;
  if (l.has("head_size")) {
    const json& h = l.at("head_size");
    if (h.is_number()) {
      const double r = h.get<double>();
      if (!(r >= 0.05 && r <= 0.15)) l.fail("head_size", "radius out of range: " + h.dump() + " (0.05 to 0.15 m)");
      out.head_radius_m = r;
    } else if (h == "small") {
      out.head_radius_m = hrtf::head_radius_m(hrtf::HeadSize::small);
    } else if (h == "medium") {
      out.head_radius_m = hrtf::head_radius_m(hrtf::HeadSize::medium);
    } else if (h == "large") {
      out.head_radius_m = hrtf::head_radius_m(hrtf::HeadSize::large);
    } else if (h != "measured") {
      l.fail("head_size", "expected measured, small, medium, large or a radius in metres, got " + h.dump());
    }
  }
  out.position = l.vec3("position", {0, 0, 0});
  out.yaw_deg = l.number("yaw_deg", 0, -360, 360);
  out.pitch_deg = l.number("pitch_deg", 0, -90, 90);
  out.roll_deg = l.number("roll_deg", 0, -360, 360);
  l.done();
  return out;
}

/// "beds": the Ambisonic recordings played around the listener.
std::vector<SceneBed> parse_beds(Fields& f, std::string_view origin, const std::filesystem::path& base) {
  std::vector<SceneBed> out;
  const json& beds = f.at("beds");
  if (!beds.is_array()) f.fail("beds", "expected an array of beds");
  for (std::size_t i = 0; i < beds.size(); ++i) {
    Fields bf(beds[i], origin, "beds[" + std::to_string(i) + "]");
    SceneBed b;
    b.name = bf.text("name", "bed " + std::to_string(i + 1));
    if (!bf.has("path")) bf.fail("path", "missing (an Ambisonic file)");
    b.path = resolve(base, bf.text("path", ""));
    b.convention = bf.text("convention", "ambix");
    if (b.convention != "ambix" && b.convention != "n3d" && b.convention != "fuma")
      bf.fail("convention", "unknown convention '" + b.convention + "' (ambix, n3d, fuma)");
    b.gain_db = bf.number("gain_db", 0, -120, 40);
    b.yaw_deg = bf.number("yaw_deg", 0, -360, 360);
    b.pitch_deg = bf.number("pitch_deg", 0, -90, 90);
    b.roll_deg = bf.number("roll_deg", 0, -360, 360);
    if (bf.has("loop")) {
      if (!bf.at("loop").is_boolean()) bf.fail("loop", "expected true or false");
      b.loop = bf.at("loop").get<bool>();
    }
    bf.done();
    out.push_back(std::move(b));
  }
  return out;
}

/// One entry of "sources": its signal, where it is or moves, how it fades.
SceneSource parse_source(const json& j, std::size_t i, std::string_view origin, const std::filesystem::path& base) {
  const std::string where = "sources[" + std::to_string(i) + "]";
  Fields sf(j, origin, where);
  SceneSource src;
  src.name = sf.text("name", "source " + std::to_string(i + 1));
  if (!sf.has("signal")) sf.fail("signal", "missing");
  src.signal = parse_signal(sf.at("signal"), origin, where + ".signal", base);
  if (sf.has("path") && sf.has("position")) sf.fail("path", "a source has a position or a path, not both");
  if (sf.has("path")) src.path = parse_path(sf.at("path"), origin, where + ".path");
  src.position = sf.vec3("position", {0, 0, -1});
  if (src.path) src.position = path_position(*src.path, 0.0);
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
  return src;
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
  s.origin = std::string(origin);
  s.description = f.text("description", "");
  s.duration_s = f.number("duration_s", 5.0, 0.0, 3600.0);
  s.sample_rate = f.number("sample_rate", 48000.0, 8000.0, 192000.0);
  s.room = f.text("room", "none");
  if (!is_room_name(s.room)) f.fail("room", unknown_room_message(s.room));
  s.reverb = f.text("reverb", "fdn");
  if (s.reverb != "fdn" && s.reverb != "schroeder")
    f.fail("reverb", "unknown reverb '" + s.reverb + "' (available: fdn, schroeder)");
  s.doppler_factor = f.number("doppler_factor", 1.0, 0.0, 10.0);
  s.speed_of_sound = f.number("speed_of_sound", 343.3, 1.0, 10000.0);
  if (f.has("listener")) s.listener = parse_listener(f.at("listener"), origin);
  if (f.has("pose_track")) s.pose_track = resolve(base, f.text("pose_track", ""));
  s.quality = f.text("quality", "direct");
  if (!quality_order(s.quality)) f.fail("quality", "unknown quality '" + s.quality + "' (direct, ambisonic:1 to ambisonic:7)");
  if (f.has("beds")) s.beds = parse_beds(f, origin, base);
  if (!f.has("sources") && !s.beds.empty()) {
    f.done();
    return s;
  }
  if (!f.has("sources") || !f.at("sources").is_array()) f.fail("sources", "expected an array of sources");
  const json& arr = f.at("sources");
  for (std::size_t i = 0; i < arr.size(); ++i) s.sources.push_back(parse_source(arr[i], i, origin, base));
  f.done();
  return s;
}

std::optional<int> quality_order(std::string_view q) {
  if (q == "direct") return 0;
  constexpr std::string_view prefix = "ambisonic:";
  if (q.size() != prefix.size() + 1 || q.substr(0, prefix.size()) != prefix) return std::nullopt;
  const char n = q.back();
  if (n < '1' || n > '7') return std::nullopt;
  return n - '0';
}

bool is_room_name(std::string_view name) { return name == "none" || audio::find_room_preset(name) != nullptr; }

std::string unknown_room_message(std::string_view name) {
  return "unknown room preset '" + std::string(name) + "' (available: none, " + audio::room_preset_names() + ")";
}

std::string checked_room_name(std::string_view name, std::string_view origin) {
  if (!is_room_name(name)) throw InputError::at(origin, 0, "", unknown_room_message(name));
  return std::string(name);
}

Vec3 source_position(const SceneSource& s, double t) { return s.path ? path_position(*s.path, t) : s.position; }

Scene load_scene(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError::at(path.string(), 0, "", "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), path.string(), path.parent_path());
}

}  // namespace earshot::scenes
