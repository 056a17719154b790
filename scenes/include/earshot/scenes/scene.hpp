// Scene JSON: what `earshot render` plays (contract in docs/ARCHITECTURE.md).
//   {"description": "what the scene is",            (optional, free text)
//    "duration_s": 5, "sample_rate": 48000, "room": "none", "reverb": "fdn",
//    "doppler_factor": 1, "speed_of_sound": 343.3,
//    "listener": {"position": [0,0,0], "yaw_deg": 0, "pitch_deg": 0, "roll_deg": 0,
//                 "head_size": "measured"},
//    "pose_track": "poses.csv",                       (optional)
//    "sources": [{"name": "n", "signal": {"type": "noise", "seed": 1},
//                 "position": [0,0,-1], "gain_db": 0, "distance_model": "inverse-clamped",
//                 "reference_distance": 1, "rolloff": 1, "max_distance": 100,
//                 "reverb_send_db": -120, "air_absorption": 0}]}
//    "beds": [{"name": "b", "path": "field.wav", "convention": "ambix", "gain_db": 0,
//              "yaw_deg": 0, "pitch_deg": 0, "roll_deg": 0, "loop": false}],
//    "quality": "direct"}                             (or "ambisonic:N", N = 1..7)
// A bed is an Ambisonic file (WAV, CAF, W64, ... through libsndfile; ambiX
// unless "convention" says n3d or fuma; order from the channel count) played
// as a sound field around the listener, turned by its head, never moved by
// its position; yaw/pitch/roll turn the field in the world (positive yaw
// to the left). "sources" may be left out when there are beds.
// quality: the renderer tier of the point sources (the C API's ES_QUALITY).
// A source has a fixed "position" or a moving "path" (motion_path.hpp), e.g.
//   "path": {"type": "circle", "centre": [0,0,0], "radius": 2, "plane": "xz", "period_s": 8}
// Signals: noise {seed}, sine {frequency_hz}, impulse {}, file {path, loop}
// (any rate, resampled; signal_source.hpp), and the synthesised voice, talk,
// siren, birds, engine, horn, footsteps, ambience, animal (sounds.hpp).
// Shipped presets: presets.hpp.
// room: "none" or a room preset (audio/room_presets.hpp, e.g. "concert-hall");
// reverb: its late reverb, "fdn" (default) or "schroeder". Sources reach it
// through reverb_send_db.
// head_size: "measured" (the HRTF's own ITD) or a spherical-head ITD for
// "small", "medium", "large" heads or a radius in metres (the thesis's
// listener sizes). air_absorption: OpenAL's factor (0 = none, 1 = normal air).
// Unknown fields are errors; every error names the file and the field.
// Relative paths inside a scene are relative to the scene file.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "earshot/audio/distance_model.hpp"
#include "earshot/scenes/motion_path.hpp"
#include "earshot/scenes/sounds.hpp"

namespace earshot::scenes {

/// A source's sound. `type` picks one generator; only its fields are used
/// (the synthesised sounds' fields are documented in sounds.hpp).
struct Signal {
  enum class Type { noise, sine, impulse, file, voice, talk, siren, birds, engine, horn, footsteps, ambience, animal };
  Type type = Type::noise;
  std::uint64_t seed = 1;
  double frequency_hz = 440.0;
  std::filesystem::path path;  ///< file: any rate, resampled to the scene's
  bool loop = false;           ///< file: start again at the end (else silence)
  VoiceParams voice;
  TalkParams talk;
  SirenParams siren;
  BirdsParams birds;
  EngineParams engine;
  HornParams horn;
  FootstepsParams footsteps;
  AmbienceParams ambience;
  AnimalParams animal;
};

struct SceneSource {
  std::string name;
  Signal signal;
  std::array<double, 3> position{0, 0, -1};
  std::optional<MotionPath> path;  ///< replaces position when set
  double gain_db = 0.0;
  audio::DistanceParams distance{};
  double reverb_send_db = -120.0;
  double air_absorption = 0.0;
};

/// An Ambisonic bed: a file played as a sound field.
struct SceneBed {
  std::string name;
  std::filesystem::path path;    ///< resolved against the scene's directory
  std::string convention = "ambix";  ///< "ambix", "n3d" or "fuma"
  double gain_db = 0.0;
  double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;  ///< the field's orientation in the world
  bool loop = false;
};

struct SceneListener {
  std::array<double, 3> position{0, 0, 0};
  double yaw_deg = 0, pitch_deg = 0, roll_deg = 0;
  std::optional<double> head_radius_m;  ///< none: the HRTF's measured ITD
};

struct Scene {
  std::string origin;            ///< where it was read from (file name), for errors
  std::string description;       ///< what the scene is, its little story
  double duration_s = 5.0;
  double sample_rate = 48000.0;
  std::string room = "none";    ///< "none" or a room preset name
  std::string reverb = "fdn";   ///< late reverb of the room: "fdn" or "schroeder"
  double doppler_factor = 1.0;   ///< OpenAL's; 0 removes propagation delay and Doppler
  double speed_of_sound = 343.3; ///< m/s
  SceneListener listener;
  std::optional<std::filesystem::path> pose_track;
  std::vector<SceneSource> sources;
  std::vector<SceneBed> beds;
  std::string quality = "direct";  ///< "direct" or "ambisonic:N"
};

/// The order a quality names: 0 for "direct", N for "ambisonic:N" (1..7);
/// nullopt for anything else.
[[nodiscard]] std::optional<int> quality_order(std::string_view quality);

/// True for "none" and every room preset name (audio/room_presets.hpp).
[[nodiscard]] bool is_room_name(std::string_view name);
/// "unknown room preset 'NAME' (available: none, ...)".
[[nodiscard]] std::string unknown_room_message(std::string_view name);
/// `name` when is_room_name, else throws earshot::InputError naming
/// `origin` (e.g. "--room"): for a room given outside Scene JSON.
[[nodiscard]] std::string checked_room_name(std::string_view name, std::string_view origin);

/// Where a source is at time t: its path's position, else its fixed position.
[[nodiscard]] Vec3 source_position(const SceneSource& s, double t);

/// Parses Scene JSON text; `origin` names it in errors; relative paths are
/// resolved against `base_dir`. Throws earshot::InputError.
[[nodiscard]] Scene parse_scene(std::string_view json_text, std::string_view origin,
                                const std::filesystem::path& base_dir = {});
[[nodiscard]] Scene load_scene(const std::filesystem::path& path);

}  // namespace earshot::scenes
