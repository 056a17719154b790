#include "live_demo.hpp"

#include <poll.h>
#include <sys/resource.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <optional>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <thread>
#include <vector>

#include "audio_output.hpp"
#include "block_render.hpp"
#include "keys.hpp"
#ifdef EARSHOT_DEMO_WINDOW
#include "window.hpp"
#endif
#include "earshot/earshot.h"
#include "earshot/audio/room_presets.hpp"
#include "earshot/errors.hpp"
#include "earshot/scenes/motion_path.hpp"
#include "earshot/scenes/presets.hpp"
#include "earshot/scenes/scene.hpp"
#include "earshot/scenes/signal_source.hpp"

namespace earshot::demo {
namespace {

/// Owns a plugin world (RAII).
class World {
 public:
  explicit World(const ESworldparams& p) {
    if (const ESenum e = esCreateWorld(&p, &w_); e != ES_OK)
      throw std::runtime_error(std::string("cannot create the audio world: ") + esGetErrorString(e));
  }
  ~World() { esDestroyWorld(w_); }
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  [[nodiscard]] ESworld id() const { return w_; }
  void check(ESenum e, const char* what) const {
    if (e != ES_OK) throw std::runtime_error(std::string(what) + ": " + esGetErrorMessage(w_));
  }

 private:
  ESworld w_ = 0;
};

void generate(void* user, float* out, ESuint frames) {
  static_cast<scenes::SignalSource*>(user)->generate(std::span<float>(out, frames));
}

ESenum distance_model(audio::DistanceModel m) {
  using M = audio::DistanceModel;
  switch (m) {
    case M::none: return ES_NONE;
    case M::inverse: return ES_INVERSE_DISTANCE;
    case M::inverse_clamped: return ES_INVERSE_DISTANCE_CLAMPED;
    case M::linear: return ES_LINEAR_DISTANCE;
    case M::linear_clamped: return ES_LINEAR_DISTANCE_CLAMPED;
    case M::exponent: return ES_EXPONENT_DISTANCE;
    case M::exponent_clamped: return ES_EXPONENT_DISTANCE_CLAMPED;
  }
  return ES_INVERSE_DISTANCE_CLAMPED;
}

double yaw_deg(const float q[4]) {
  const double fx = -2 * (q[1] * q[3] + q[0] * q[2]), fz = -(1 - 2 * (q[1] * q[1] + q[2] * q[2]));
  return std::atan2(-fx, -fz) * 180.0 / std::numbers::pi;
}

/// The terminal in raw, non-blocking mode while it lives (keys without Enter).
class RawTerminal {
 public:
  RawTerminal() : ok_(isatty(STDIN_FILENO) && tcgetattr(STDIN_FILENO, &saved_) == 0) {
    if (!ok_) return;
    termios raw = saved_;
    raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
    tcsetattr(STDIN_FILENO, TCSANOW, &raw);
  }
  ~RawTerminal() {
    if (ok_) tcsetattr(STDIN_FILENO, TCSANOW, &saved_);
  }
  RawTerminal(const RawTerminal&) = delete;
  RawTerminal& operator=(const RawTerminal&) = delete;
  /// A key pressed, or 0.
  [[nodiscard]] char key() const {
    if (!ok_) return 0;
    pollfd p{STDIN_FILENO, POLLIN, 0};
    char c = 0;
    if (poll(&p, 1, 0) > 0 && read(STDIN_FILENO, &c, 1) == 1) return c;
    return 0;
  }

 private:
  termios saved_{};
  bool ok_;
};

void write_wav(const std::filesystem::path& path, const std::vector<float>& lr, std::size_t n, unsigned rate) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw InputError::at(path.string(), 0, "", "cannot write");
  auto u32 = [&](std::uint32_t v) { f.write(reinterpret_cast<const char*>(&v), 4); };
  auto u16 = [&](std::uint16_t v) { f.write(reinterpret_cast<const char*>(&v), 2); };
  const auto bytes = static_cast<std::uint32_t>(n * sizeof(float));
  f.write("RIFF", 4), u32(36 + bytes), f.write("WAVEfmt ", 8), u32(16), u16(3), u16(2), u32(rate),
      u32(rate * 8), u16(8), u16(32), f.write("data", 4), u32(bytes);
  f.write(reinterpret_cast<const char*>(lr.data()), static_cast<std::streamsize>(bytes));
}

}  // namespace

void list_devices() {
  AudioOutput out;
  std::printf("Output devices (* default):\n%s", describe_devices(out.devices()).c_str());
}

namespace {

/// Sounds and paths to pick from: the current scene's, then every preset's.
struct Library {
  std::vector<std::string> sound_names, path_names{"fixed position"};
  std::vector<scenes::Signal> sounds;
  std::vector<scenes::MotionPath> paths;  ///< paths[i] is path_names[i + 1]

  void add(const std::string& scene_name, const scenes::Scene& s) {
    for (const auto& src : s.sources) {
      sound_names.push_back(scene_name + ": " + src.name);
      sounds.push_back(src.signal);
      if (src.path) {
        path_names.push_back(scene_name + ": " + src.name);
        paths.push_back(*src.path);
      }
    }
  }
};

/// "none" and every room preset the plugin knows (esReverbPreset's names).
std::vector<std::string> room_names() {
  std::vector<std::string> r{"none"};
  for (const auto& p : audio::room_presets()) r.emplace_back(p.name);
  return r;
}
const std::vector<std::string> kRooms = room_names();
const std::vector<std::string> kDistanceModels{"none", "inverse", "inverse clamped", "linear", "linear clamped",
                                               "exponent", "exponent clamped"};
constexpr std::array<ESenum, 7> kDistanceEnums{ES_NONE,
                                               ES_INVERSE_DISTANCE,
                                               ES_INVERSE_DISTANCE_CLAMPED,
                                               ES_LINEAR_DISTANCE,
                                               ES_LINEAR_DISTANCE_CLAMPED,
                                               ES_EXPONENT_DISTANCE,
                                               ES_EXPONENT_DISTANCE_CLAMPED};

float db(double d) { return static_cast<float>(std::pow(10.0, d / 20.0)); }

/// The scene on the control side: its sources in the world, fed by callback
/// sources, moved along their paths. Sounds replaced or dropped are kept
/// (retired) until the player is destroyed, after the audio stopped: the
/// audio thread may still be inside one of them when it is replaced.
class Player {
 public:
  Player(const World& world, double rate) : world_(world), rate_(rate) {}
  ~Player() {
    for (ESsource id : ids_) esDeleteSource(world_.id(), id);
  }
  Player(const Player&) = delete;
  Player& operator=(const Player&) = delete;

  /// Replaces the sources and the room by the scene's (the sounds are made
  /// first: a file that cannot be read throws before anything changes).
  void load(scenes::Scene scene) {
    std::vector<std::unique_ptr<scenes::SignalSource>> made;
    for (const auto& s : scene.sources) made.push_back(std::make_unique<scenes::SignalSource>(s.signal, rate_));
    const ESworld w = world_.id();
    for (ESsource id : ids_) esDeleteSource(w, id);
    ids_.clear();
    for (auto& old : sounds_) retired_.push_back(std::move(old));
    sounds_ = std::move(made);
    scene_ = std::move(scene);
    const auto& L = scene_.listener.position;
    world_.check(esListener3f(w, ES_POSITION, float(L[0]), float(L[1]), float(L[2])), "listener");
    set_room(scene_.room);
    for (std::size_t i = 0; i < scene_.sources.size(); ++i) {
      const auto& s = scene_.sources[i];
      ESsource id = 0;
      world_.check(esCreateSource(w, &id), "source");
      ids_.push_back(id);
      world_.check(esSourceCallback(w, id, &generate, sounds_[i].get()), "source sound");
      world_.check(esSourcef(w, id, ES_GAIN, db(s.gain_db)), "source gain");
      world_.check(esSourcei(w, id, ES_DISTANCE_MODEL, distance_model(s.distance.model)), "distance model");
      world_.check(esSourcef(w, id, ES_REFERENCE_DISTANCE, float(s.distance.reference_distance)), "distance");
      world_.check(esSourcef(w, id, ES_ROLLOFF_FACTOR, float(s.distance.rolloff)), "rolloff");
      world_.check(esSourcef(w, id, ES_MAX_DISTANCE, float(std::min(s.distance.max_distance, 3.0e38))), "max distance");
      world_.check(esSourcef(w, id, ES_REVERB_SEND, s.reverb_send_db <= -120 ? 0.0f : db(s.reverb_send_db)), "send");
      world_.check(esSourcef(w, id, ES_AIR_ABSORPTION_FACTOR, float(s.air_absorption)), "air absorption");
      const auto x = scenes::source_position(s, 0.0);
      world_.check(esSource3f(w, id, ES_POSITION, float(x[0]), float(x[1]), float(x[2])), "position");
      world_.check(esSourcePlay(w, id), "play");
    }
    t0_ = -1;  // paths start again at the next move()
  }

  void set_room(const std::string& room) {
    const ESworld w = world_.id();
    if (room != "none") world_.check(esReverbPreset(w, room.c_str()), "room");
    world_.check(esReverbi(w, ES_REVERB_ENABLED, room != "none" ? 1 : 0), "room");
    scene_.room = room;
  }

  /// Moves the sources on paths to where they are `t` seconds into the scene.
  void move(double t) {
    if (t0_ < 0) t0_ = t;
    for (std::size_t i = 0; i < ids_.size(); ++i)
      if (scene_.sources[i].path) {
        const auto x = position(i, t);
        esSource3f(world_.id(), ids_[i], ES_POSITION, float(x[0]), float(x[1]), float(x[2]));
      }
  }
  [[nodiscard]] scenes::Point3 position(std::size_t i, double t) const {
    return scenes::source_position(scene_.sources[i], std::max(0.0, t - std::max(t0_, 0.0)));
  }

  void set_sound(std::size_t i, const scenes::Signal& sig) {
    auto made = std::make_unique<scenes::SignalSource>(sig, rate_);  // may throw: nothing changed
    world_.check(esSourceCallback(world_.id(), ids_[i], &generate, made.get()), "source sound");
    retired_.push_back(std::move(sounds_[i]));
    sounds_[i] = std::move(made);
    scene_.sources[i].signal = sig;
  }
  void set_path(std::size_t i, std::optional<scenes::MotionPath> path, double t) {
    if (!path) scene_.sources[i].position = position(i, t);  // stays where it is
    scene_.sources[i].path = std::move(path);
    move(t);
  }
  void set_position(std::size_t i, const std::array<float, 3>& p) {
    scene_.sources[i].path.reset();
    scene_.sources[i].position = {p[0], p[1], p[2]};
    esSource3f(world_.id(), ids_[i], ES_POSITION, p[0], p[1], p[2]);
  }
  void set_gain_distance(std::size_t i, float gain_db, int model, float rolloff, float reference) {
    const ESworld w = world_.id();
    world_.check(esSourcef(w, ids_[i], ES_GAIN, db(gain_db)), "gain");
    world_.check(esSourcei(w, ids_[i], ES_DISTANCE_MODEL, kDistanceEnums[std::size_t(model) % 7]), "distance model");
    world_.check(esSourcef(w, ids_[i], ES_ROLLOFF_FACTOR, rolloff), "rolloff");
    world_.check(esSourcef(w, ids_[i], ES_REFERENCE_DISTANCE, reference), "reference distance");
  }

  [[nodiscard]] const scenes::Scene& scene() const { return scene_; }

 private:
  const World& world_;
  double rate_;
  double t0_ = -1;
  scenes::Scene scene_;
  std::vector<ESsource> ids_;
  std::vector<std::unique_ptr<scenes::SignalSource>> sounds_, retired_;
};

/// Stops the audio before the sounds it reads go (declared after Player).
struct StopAudio {
  AudioOutput& out;
  ~StopAudio() { out.stop(); }
};

const char* state_name(ESenum s) {
  switch (s) {
    case ES_TRACKER_NONE: return "none";
    case ES_TRACKER_SEARCHING: return "searching";
    case ES_TRACKER_CONNECTED: return "connected";
    case ES_TRACKER_TRACKING: return "tracking";
    case ES_TRACKER_LOST: return "lost";
    case ES_TRACKER_DISCONNECTED: return "disconnected";
    default: return "?";
  }
}

/// The tracker as the demo shows it: the plugin's state, or why it failed to start.
struct TrackerView {
  std::string spec, state = "none", message, failed;  ///< failed: esAttachTracker's message
  EStrackerstate st{};
  bool alarm = false;

  void refresh(ESworld w) {
    if (!failed.empty()) {
      state = "failed", message = failed + "; the head is held straight", alarm = true;
      return;
    }
    st = EStrackerstate{};
    st.size = sizeof st;
    if (esGetTrackerState(w, &st) != ES_OK) return;
    state = state_name(st.state), message = st.message;
    alarm = st.state == ES_TRACKER_SEARCHING ? std::string(st.message).find("no Wii Remote") != std::string::npos ||
                                                   std::string(st.message).find("permission") != std::string::npos
                                             : st.state == ES_TRACKER_DISCONNECTED;
    if (st.state == ES_TRACKER_NONE) message.clear();
  }
};

#ifdef EARSHOT_DEMO_WINDOW
constexpr int kSoftwareFps = 15;

/// True when what the window shows moved since the last call (head, sources,
/// dots, the tracker's state): frames of an unchanged view are not drawn.
bool view_changed(const WindowModel& m, const float pos[3], const float q[4], const EStrackerstate& ts) {
  static std::vector<float> last;
  std::vector<float> now{pos[0], pos[1], pos[2], q[0], q[1], q[2], q[3], float(ts.state), float(ts.dot_count)};
  for (const auto& s : m.sources) now.insert(now.end(), s.position.begin(), s.position.end());
  for (ESuint i = 0; i < ts.dot_count && i < ES_TRACKER_MAX_DOTS; ++i) {
    now.push_back(ts.dots[i].x);
    now.push_back(ts.dots[i].y);
  }
  bool moved = now.size() != last.size();
  for (std::size_t i = 0; !moved && i < now.size(); ++i) moved = std::abs(now[i] - last[i]) > 1e-4f;
  last = std::move(now);
  return moved;
}
#endif

scenes::Scene load_scene_arg(const std::string& arg, std::string& name) {
  const auto file = scenes::resolve_scene_argument(arg);
  name = file.filename().string();
  return scenes::load_scene(file);
}

}  // namespace

long run_live(const LiveOptions& o) {
  // A scene with errors is said, and Circles plays instead (the audio goes on).
  std::string scene_name, scene_error;
  scenes::Scene scene;
  try {
    scene = load_scene_arg(o.scene, scene_name);
  } catch (const InputError& e) {
    scene_error = std::string(e.what()) + " -- playing circles instead";
    std::fprintf(stderr, "earshot demo: %s\n", scene_error.c_str());
    scene = load_scene_arg("circles", scene_name);
  }
  if (!o.room.empty())
    scene.room = scenes::parse_scene(R"({"room": ")" + o.room + R"(", "sources": []})", "--room").room;
  const double rate = scene.sample_rate;

  AudioOutput out;
  const DeviceInfo dev = out.choose(o.device);

  ESworldparams p;
  esWorldParamsDefault(&p);
  p.sample_rate = static_cast<ESuint>(rate);
  p.block_size = static_cast<ESuint>(o.buffer);
  p.max_sources = 64;  // room for any scene picked later
  if (scene.listener.head_radius_m) p.head_radius_m = static_cast<float>(*scene.listener.head_radius_m);
  if (!o.hrtf.empty()) p.hrtf_path = o.hrtf.c_str();
  World world(p);
  const ESworld w = world.id();

  // What can be picked: the presets (and the file given), sounds and paths.
  std::vector<std::string> scene_args = scenes::preset_names();
  Library lib;
  lib.add(std::filesystem::path(scene_name).stem().string(), scene);
  for (const auto& name : scene_args) {
    if (name + ".json" == scene_name) continue;
    try {
      std::string n;
      lib.add(name, load_scene_arg(name, n));
    } catch (const std::exception&) {
      // a preset that does not load is simply not offered
    }
  }
  if (std::find(scene_args.begin(), scene_args.end(), std::filesystem::path(scene_name).stem().string()) ==
          scene_args.end() &&
      scene_error.empty())
    scene_args.push_back(o.scene);  // the file given on the command line

  Player player(world, rate);
  player.load(scene);

  TrackerView tracker;
  tracker.spec = o.tracker.empty() ? "none" : o.tracker;
  if (!o.tracker.empty() && o.tracker != "none") {
    if (esAttachTracker(w, o.tracker.c_str()) != ES_OK) {
      tracker.failed = esGetErrorMessage(w);
      std::fprintf(stderr, "earshot demo: tracker %s failed: %s; the head is held straight\n", o.tracker.c_str(),
                   tracker.failed.c_str());
    } else {
      esRecenter(w);
    }
  }

  AudioSide side;
  side.world = w;
  if (!o.capture.empty()) side.capture.assign(static_cast<std::size_t>(std::max(o.duration, 1.0) * rate + 2 * double(o.buffer)) * 2, 0.0f);

  out.start(dev, rate, o.buffer, &render_block, &side);
  StopAudio stop_audio{out};
  // The audio thread real-time (when the server did not already and we may):
  // a window drawn in software next to it then cannot delay its blocks.
  const std::string rt_why = out.make_audio_thread_realtime();
  std::printf("earshot demo: playing %s (%zu sources, room %s) on '%s' (%s): %lu-frame buffer, "
              "output latency %.1f ms; tracker %s\n",
              scene_name.c_str(), scene.sources.size(), player.scene().room.c_str(), dev.name.c_str(),
              dev.host_api.c_str(), o.buffer, out.latency_s() * 1e3, tracker.spec.c_str());
  std::printf("  audio thread: %s\n", rt_why.empty() ? "real-time (SCHED_FIFO)" : rt_why.c_str());
  std::printf("Keys: %s\n", keys_line().c_str());
  std::fflush(stdout);

#ifdef EARSHOT_DEMO_WINDOW
  std::unique_ptr<DemoWindow> win;
  WindowModel model;
  if (o.window && (std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY"))) {
    // The window's thread (this one, and the software rasteriser's threads it
    // starts) yields to the audio: it runs at a lower priority (nice 10) than
    // the audio thread PortAudio already started at the process's.
    // Mesa's software rasteriser draws on this thread alone (not on extra
    // threads of its own), unless the person chose otherwise: the window then
    // takes at most one core, and the other stays for the audio and the server.
    if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 10) != 0)
      std::fprintf(stderr, "earshot demo: could not lower the window thread's priority\n");
    setenv("LP_NUM_THREADS", "0", 0);
    try {
      win = std::make_unique<DemoWindow>("earshot demo");
      if (win->software())
        std::printf("  window: OpenGL in software (%s): %d frames/s at most, no anti-aliasing, "
                    "drawn at a lower priority than the audio\n",
                    win->renderer().c_str(), kSoftwareFps);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "earshot demo: %s; status on the terminal instead\n", e.what());
    }
  }
  model.device = dev.name, model.latency_ms = out.latency_s() * 1e3, model.tracker = tracker.spec;
  model.rooms = kRooms, model.distance_models = kDistanceModels;
  model.sounds = lib.sound_names, model.paths = lib.path_names, model.scenes = scene_args;
  model.message = scene_error;
  // The window's view of the scene (after every load).
  const auto describe_scene = [&] {
    const auto& sc = player.scene();
    model.scene = scene_name, model.room = sc.room;
    model.room_index = 0;
    for (std::size_t i = 0; i < model.rooms.size(); ++i)
      if (model.rooms[i] == sc.room) model.room_index = int(i);
    model.scene_index = 0;
    for (std::size_t i = 0; i < model.scenes.size(); ++i)
      if (model.scenes[i] + ".json" == scene_name || model.scenes[i] == scene_name) model.scene_index = int(i);
    model.sources.clear();
    for (const auto& s : sc.sources) {
      ViewSource v;
      v.name = s.name, v.gain_db = float(s.gain_db), v.rolloff = float(s.distance.rolloff);
      v.reference_distance = float(s.distance.reference_distance);
      for (std::size_t k = 0; k < kDistanceEnums.size(); ++k)
        if (kDistanceEnums[k] == distance_model(s.distance.model)) v.distance_model = int(k);
      const std::string own = std::filesystem::path(scene_name).stem().string() + ": " + s.name;
      for (std::size_t k = 0; k < lib.sound_names.size(); ++k)
        if (lib.sound_names[k] == own) v.sound = int(k);
      v.path_choice = s.path ? -1 : 0;  // -1: a path not in the list (a file loaded later)
      for (std::size_t k = 1; k < lib.path_names.size() && s.path; ++k)
        if (lib.path_names[k] == own) v.path_choice = int(k);
      model.sources.push_back(std::move(v));
    }
  };
  const auto sample_path = [&](std::size_t i) {
    auto& v = model.sources[i];
    v.path.clear();
    if (const auto& path = player.scene().sources[i].path)
      for (int k = 0; k <= 64; ++k) {
        const auto x = scenes::path_position(*path, k * 0.25);
        v.path.push_back({float(x[0]), float(x[1]), float(x[2])});
      }
  };
  describe_scene();
  for (std::size_t i = 0; i < model.sources.size(); ++i) sample_path(i);
#endif
  // Scene and room changes (keys or window): on this, the control thread.
  std::string last_message_said;
  auto say = [&](const std::string& m) {
    std::fprintf(stderr, "%searshot demo: %s\n", isatty(STDERR_FILENO) ? "\n" : "", m.c_str());
#ifdef EARSHOT_DEMO_WINDOW
    model.message = m;
#endif
  };
  std::size_t scene_pick = 0;
  for (std::size_t i = 0; i < scene_args.size(); ++i)
    if (scene_args[i] + ".json" == scene_name) scene_pick = i;
  const auto switch_scene = [&](const std::string& arg, double t) {
    try {
      std::string name;
      scenes::Scene next = load_scene_arg(arg, name);
      player.load(std::move(next));
      player.move(t);
      scene_name = name;
      say("scene " + scene_name + " (" + std::to_string(player.scene().sources.size()) + " sources, room " +
          player.scene().room + ")");
#ifdef EARSHOT_DEMO_WINDOW
      describe_scene();
      for (std::size_t i = 0; i < model.sources.size(); ++i) sample_path(i);
#endif
    } catch (const std::exception& e) {
      say(std::string(e.what()) + " -- still playing " + scene_name);
    }
  };
  std::size_t room_pick = 0;
  for (std::size_t i = 0; i < kRooms.size(); ++i)
    if (kRooms[i] == player.scene().room) room_pick = i;
  const auto switch_room = [&](const std::string& room) {
    try {
      player.set_room(room);
      say("room " + room);
    } catch (const std::exception& e) {
      say(e.what());
    }
  };

  auto last_frame = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  std::chrono::milliseconds last_frame_cost{0};
  auto last_tracker = last_frame;
  RawTerminal term;
  std::vector<std::pair<double, double>> poses;  // t, yaw
  const bool status = isatty(STDERR_FILENO);
  const auto& st = out.stats();
  auto last_status = std::chrono::steady_clock::now();
  std::string pending_said;
  tracker.refresh(w);
  if (!tracker.failed.empty()) last_message_said = tracker.state + ": " + tracker.message;  // said above
  auto pending_since = last_status;
  for (;;) {
    const double t = double(st.blocks.load()) * double(o.buffer) / rate;
    if (o.duration > 0 && t >= o.duration) break;
    const char k = term.key();
    if (k == 'q' || k == 'Q' || k == 27) break;
    if (k == 'r' || k == 'R') esRecenter(w);
    if ((k == 'n' || k == 'N') && !scene_args.empty()) {
      scene_pick = (scene_pick + 1) % scene_args.size();
      switch_scene(scene_args[scene_pick], t);
    }
    if (k == 'm' || k == 'M') {
      room_pick = (room_pick + 1) % kRooms.size();
      switch_room(kRooms[room_pick]);
    }
    player.move(t);
    float pos[3], q[4];
    esGetHeadPose(w, pos, q);
    poses.emplace_back(t, yaw_deg(q));
    const auto now = std::chrono::steady_clock::now();
    if (now - last_tracker >= std::chrono::milliseconds(100)) {
      last_tracker = now;
      tracker.refresh(w);
      // What the tracker says goes to the terminal too, once per change: at
      // once when it is an alarm (no remote, disconnected), else once it held
      // for half a second (a frame or two of 'lost' is not news).
      const std::string said = tracker.state + ": " + tracker.message;
      if (said != pending_said) pending_said = said, pending_since = now;
      if (!tracker.message.empty() && said != last_message_said &&
          (tracker.alarm || now - pending_since >= std::chrono::milliseconds(500))) {
        std::fprintf(stderr, "%searshot demo: tracker %s %s: %s\n", status ? "\n" : "", tracker.spec.c_str(),
                     tracker.state.c_str(), tracker.message.c_str());
        last_message_said = said;
      }
    }
#ifdef EARSHOT_DEMO_WINDOW
    // 30 frames a second at most (software OpenGL: kSoftwareFps, and never
    // more than half of this thread's time), drawn at a lower priority than
    // the audio; nothing moved and nothing typed: 4 frames a second.
    const auto frame_gap = std::max(win && win->software() ? std::chrono::milliseconds(1000 / kSoftwareFps)
                                                            : std::chrono::milliseconds(33),
                                    2 * last_frame_cost);
    if (win && now - last_frame >= frame_gap) {
      for (std::size_t i = 0; i < model.sources.size(); ++i) {
        const auto x = player.position(i, t);
        model.sources[i].position = {float(x[0]), float(x[1]), float(x[2])};
      }
    }
    if (win && now - last_frame >= frame_gap &&
        (now - last_frame >= std::chrono::milliseconds(250) || view_changed(model, pos, q, tracker.st))) {
      last_frame = now;
      model.time_s = t, model.load = st.load_last.load(), model.load_max = st.load_max.load();
      model.xruns = st.xruns.load(), model.blocks = st.blocks.load();
      const auto& L = player.scene().listener.position;
      model.head_position = {pos[0] + float(L[0]), pos[1] + float(L[1]), pos[2] + float(L[2])};
      model.head_orientation = {q[0], q[1], q[2], q[3]};
      model.tracker_state = tracker.state, model.tracker_message = tracker.message;
      model.tracker_alarm = tracker.alarm, model.tracker_rate = tracker.st.rate_hz;
      model.tracker_frames = tracker.st.frames;
      model.dots.clear();
      for (ESuint i = 0; i < tracker.st.dot_count && i < ES_TRACKER_MAX_DOTS; ++i)
        model.dots.push_back({tracker.st.dots[i].x, tracker.st.dots[i].y, tracker.st.dots[i].size,
                              tracker.st.dots[i].label});
      const WindowActions act = win->frame(model);
      last_frame_cost = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - now);
      if (act.quit) break;
      if (act.recenter) esRecenter(w);
      if (act.next_scene && !scene_args.empty()) {
        scene_pick = (scene_pick + 1) % scene_args.size();
        switch_scene(scene_args[scene_pick], t);
      } else if (act.scene_changed) {
        scene_pick = std::size_t(model.scene_index);
        switch_scene(scene_args[scene_pick], t);
      } else if (act.load_file) {
        switch_scene(model.scene_file_input, t);
      }
      if (act.next_room) {
        room_pick = (room_pick + 1) % kRooms.size();
        switch_room(kRooms[room_pick]);
      } else if (act.room_changed) {
        room_pick = std::size_t(model.room_index);
        switch_room(kRooms[room_pick]);
      }
      model.room = player.scene().room;
      for (std::size_t i = 0; i < kRooms.size(); ++i)
        if (kRooms[i] == model.room) model.room_index = int(i);
      const std::size_t n = model.sources.size();
      for (int i : act.changed_sources) {
        const auto& v = model.sources[std::size_t(i)];
        if (std::size_t(i) < n) player.set_gain_distance(std::size_t(i), v.gain_db, v.distance_model, v.rolloff,
                                                         v.reference_distance);
      }
      for (int i : act.changed_sounds) {
        const auto& v = model.sources[std::size_t(i)];
        if (std::size_t(i) >= n || v.sound < 0 || std::size_t(v.sound) >= lib.sounds.size()) continue;
        try {
          player.set_sound(std::size_t(i), lib.sounds[std::size_t(v.sound)]);
        } catch (const std::exception& e) {
          say(e.what());
        }
      }
      for (int i : act.changed_paths) {
        auto& v = model.sources[std::size_t(i)];
        if (std::size_t(i) >= n || v.path_choice < 0) continue;
        player.set_path(std::size_t(i),
                        v.path_choice == 0 ? std::nullopt
                                           : std::optional<scenes::MotionPath>(lib.paths[std::size_t(v.path_choice) - 1]),
                        t);
        sample_path(std::size_t(i));
      }
      for (int i : act.changed_positions)
        if (std::size_t(i) < n) player.set_position(std::size_t(i), model.sources[std::size_t(i)].position);
    }
#endif
    if (status && now - last_status > std::chrono::milliseconds(250)) {
      last_status = now;
      std::fprintf(stderr, "\r%6.1f s  yaw %+6.1f  tracker %s %3.0f Hz %u dots  load %4.1f%% (max %4.1f%%)  xruns %llu   ",
                   t, poses.back().second, tracker.state.c_str(), double(tracker.st.rate_hz), tracker.st.dot_count,
                   100 * st.load_last.load(), 100 * st.load_max.load(), static_cast<unsigned long long>(st.xruns.load()));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  out.stop();
#ifdef EARSHOT_DEMO_WINDOW
  if (win) {
    std::printf("  window: %ld frames drawn\n", win->frames());
    if (!o.screenshot.empty()) {
      win->screenshot(o.screenshot);
      std::printf("  screenshot %s\n", o.screenshot.c_str());
    }
  }
#endif
  if (status) std::fputc('\n', stderr);
  tracker.refresh(w);
  std::printf("  tracker %s: %s%s%s\n", tracker.spec.c_str(), tracker.state.c_str(),
              tracker.message.empty() ? "" : ": ", tracker.message.c_str());
  const auto blocks = st.blocks.load();
  const double mean = blocks ? st.load_sum.load() / double(blocks) : 0.0;
  std::printf("  played %.1f s: %llu blocks, %llu xruns, audio-thread load mean %.1f%% max %.1f%% of one core\n",
              double(blocks) * double(o.buffer) / rate, static_cast<unsigned long long>(blocks),
              static_cast<unsigned long long>(st.xruns.load()), 100 * mean, 100 * st.load_max.load());
  if (st.xruns.load() > 0)
    std::printf("  xruns between %.2f s and %.2f s\n", double(st.first_xrun_block.load()) * double(o.buffer) / rate,
                double(st.last_xrun_block.load()) * double(o.buffer) / rate);
  if (!o.capture.empty()) {
    write_wav(o.capture, side.capture, side.captured.load(), static_cast<unsigned>(rate));
    std::printf("  captured %s\n", o.capture.c_str());
  }
  if (!o.capture_poses.empty()) {
    std::ofstream f(o.capture_poses);
    f << "t,yaw_deg\n";
    for (const auto& [t, y] : poses) f << t << ',' << y << '\n';
  }
  return static_cast<long>(st.xruns.load());
}

}  // namespace earshot::demo
