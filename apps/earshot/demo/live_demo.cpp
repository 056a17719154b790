#include "live_demo.hpp"

#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
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
#ifdef EARSHOT_DEMO_WINDOW
#include "window.hpp"
#endif
#include "earshot/earshot.h"
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

long run_live(const LiveOptions& o) {
  const auto scene_file = scenes::resolve_scene_argument(o.scene);
  scenes::Scene scene = scenes::load_scene(scene_file);
  if (!o.room.empty())
    scene.room = scenes::parse_scene(R"({"room": ")" + o.room + R"(", "sources": []})", "--room").room;
  const double rate = scene.sample_rate;

  AudioOutput out;
  const DeviceInfo dev = out.choose(o.device);

  ESworldparams p;
  esWorldParamsDefault(&p);
  p.sample_rate = static_cast<ESuint>(rate);
  p.block_size = static_cast<ESuint>(o.buffer);
  p.max_sources = static_cast<ESuint>(std::max<std::size_t>(scene.sources.size(), 1));
  if (scene.listener.head_radius_m) p.head_radius_m = static_cast<float>(*scene.listener.head_radius_m);
  if (!o.hrtf.empty()) p.hrtf_path = o.hrtf.c_str();
  World world(p);
  const ESworld w = world.id();
  const auto& L = scene.listener.position;
  world.check(esListener3f(w, ES_POSITION, float(L[0]), float(L[1]), float(L[2])), "listener");
  if (scene.room != "none") {
    world.check(esReverbPreset(w, scene.room.c_str()), "room");
    world.check(esReverbi(w, ES_REVERB_ENABLED, 1), "room");
  }

  std::vector<std::unique_ptr<scenes::SignalSource>> sounds;
  std::vector<ESsource> ids;
  auto db = [](double d) { return static_cast<float>(std::pow(10.0, d / 20.0)); };
  for (const auto& s : scene.sources) {
    sounds.push_back(std::make_unique<scenes::SignalSource>(s.signal, rate));
    ESsource id = 0;
    world.check(esCreateSource(w, &id), "source");
    world.check(esSourceCallback(w, id, &generate, sounds.back().get()), "source sound");
    world.check(esSourcef(w, id, ES_GAIN, db(s.gain_db)), "source gain");
    world.check(esSourcei(w, id, ES_DISTANCE_MODEL, distance_model(s.distance.model)), "distance model");
    world.check(esSourcef(w, id, ES_REFERENCE_DISTANCE, float(s.distance.reference_distance)), "distance");
    world.check(esSourcef(w, id, ES_ROLLOFF_FACTOR, float(s.distance.rolloff)), "rolloff");
    world.check(esSourcef(w, id, ES_MAX_DISTANCE, float(std::min(s.distance.max_distance, 3.0e38))), "max distance");
    world.check(esSourcef(w, id, ES_REVERB_SEND, s.reverb_send_db <= -120 ? 0.0f : db(s.reverb_send_db)), "send");
    world.check(esSourcef(w, id, ES_AIR_ABSORPTION_FACTOR, float(s.air_absorption)), "air absorption");
    const auto x = scenes::source_position(s, 0.0);
    world.check(esSource3f(w, id, ES_POSITION, float(x[0]), float(x[1]), float(x[2])), "position");
    world.check(esSourcePlay(w, id), "play");
    ids.push_back(id);
  }

  std::string tracker_note = o.tracker;
  if (!o.tracker.empty() && o.tracker != "none") {
    if (esAttachTracker(w, o.tracker.c_str()) != ES_OK) {
      tracker_note = o.tracker + " FAILED (" + esGetErrorMessage(w) + "); head held straight";
      std::fprintf(stderr, "earshot demo: tracker %s\n", tracker_note.c_str());
    } else {
      esRecenter(w);
    }
  }

  AudioSide side;
  side.world = w;
  if (!o.capture.empty()) side.capture.assign(static_cast<std::size_t>(std::max(o.duration, 1.0) * rate + 2 * double(o.buffer)) * 2, 0.0f);

  out.start(dev, rate, o.buffer, &render_block, &side);
  std::printf("earshot demo: playing %s (%zu sources, room %s) on '%s' (%s): %lu-frame buffer, "
              "output latency %.1f ms; tracker %s\n",
              scene_file.c_str(), scene.sources.size(), scene.room.c_str(), dev.name.c_str(), dev.host_api.c_str(),
              o.buffer, out.latency_s() * 1e3, tracker_note.c_str());
  std::printf("Keys: r recenter, q quit\n");
  std::fflush(stdout);

#ifdef EARSHOT_DEMO_WINDOW
  std::unique_ptr<DemoWindow> win;
  WindowModel model;
  if (o.window && (std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY"))) {
    try {
      win = std::make_unique<DemoWindow>("earshot demo - " + scene_file.filename().string());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "earshot demo: %s; status on the terminal instead\n", e.what());
    }
  }
  model.scene = scene_file.filename().string(), model.room = scene.room, model.tracker = tracker_note;
  model.device = dev.name, model.latency_ms = out.latency_s() * 1e3;
  model.rooms = {"none", "living-room", "small-room", "medium-room", "large-room", "concert-hall", "cathedral",
                 "generic"};
  for (std::size_t i = 0; i < model.rooms.size(); ++i)
    if (model.rooms[i] == scene.room) model.room_index = int(i);
  for (const auto& s : scene.sources) {
    ViewSource v;
    v.name = s.name, v.gain_db = float(s.gain_db), v.rolloff = float(s.distance.rolloff);
    if (s.path)
      for (int k = 0; k <= 64; ++k) {
        const auto x = scenes::path_position(*s.path, k * 0.25);
        v.path.push_back({float(x[0]), float(x[1]), float(x[2])});
      }
    model.sources.push_back(std::move(v));
  }
#endif
  auto last_frame = std::chrono::steady_clock::now();
  RawTerminal term;
  std::vector<std::pair<double, double>> poses;  // t, yaw
  const bool status = isatty(STDERR_FILENO);
  const auto& st = out.stats();
  auto last_status = std::chrono::steady_clock::now();
  for (;;) {
    const double t = double(st.blocks.load()) * double(o.buffer) / rate;
    if (o.duration > 0 && t >= o.duration) break;
    const char k = term.key();
    if (k == 'q' || k == 'Q' || k == 27) break;
    if (k == 'r' || k == 'R') esRecenter(w);
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (scene.sources[i].path) {
        const auto x = scenes::source_position(scene.sources[i], t);
        esSource3f(w, ids[i], ES_POSITION, float(x[0]), float(x[1]), float(x[2]));
      }
    float pos[3], q[4];
    esGetHeadPose(w, pos, q);
    poses.emplace_back(t, yaw_deg(q));
#ifdef EARSHOT_DEMO_WINDOW
    // 30 frames a second: a software-rendered window (Xvfb, llvmpipe) must not starve the audio.
    if (win && std::chrono::steady_clock::now() - last_frame >= std::chrono::milliseconds(33)) {
      last_frame = std::chrono::steady_clock::now();
      model.time_s = t, model.load = st.load_last.load(), model.load_max = st.load_max.load();
      model.xruns = st.xruns.load(), model.blocks = st.blocks.load();
      model.head_position = {pos[0] + float(L[0]), pos[1] + float(L[1]), pos[2] + float(L[2])};
      model.head_orientation = {q[0], q[1], q[2], q[3]};
      for (std::size_t i = 0; i < ids.size(); ++i) {
        const auto x = scenes::source_position(scene.sources[i], t);
        model.sources[i].position = {float(x[0]), float(x[1]), float(x[2])};
      }
      const WindowActions act = win->frame(model);
      if (act.quit) break;
      if (act.recenter) esRecenter(w);
      if (act.room_changed) {
        const auto& r = model.rooms[std::size_t(model.room_index)];
        const bool on = r != "none";
        if (on && esReverbPreset(w, r.c_str()) != ES_OK) model.message = esGetErrorMessage(w);
        esReverbi(w, ES_REVERB_ENABLED, on ? 1 : 0);
      }
      for (int i : act.changed_sources) {
        esSourcef(w, ids[std::size_t(i)], ES_GAIN, db(model.sources[std::size_t(i)].gain_db));
        esSourcef(w, ids[std::size_t(i)], ES_ROLLOFF_FACTOR, model.sources[std::size_t(i)].rolloff);
      }
    }
#endif
    const auto now = std::chrono::steady_clock::now();
    if (status && now - last_status > std::chrono::milliseconds(250)) {
      last_status = now;
      std::fprintf(stderr, "\r%6.1f s  head yaw %+6.1f deg  load %4.1f%% (max %4.1f%%)  xruns %llu   ", t,
                   poses.back().second, 100 * st.load_last.load(), 100 * st.load_max.load(),
                   static_cast<unsigned long long>(st.xruns.load()));
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
