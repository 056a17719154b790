#include "window_view.hpp"

#ifdef EARSHOT_DEMO_WINDOW
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "earshot/host/distance_models.hpp"
#include "window.hpp"
#endif

namespace earshot::demo {

#ifdef EARSHOT_DEMO_WINDOW
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;
constexpr int kSoftwareFps = 15;

/// The window's view of source `i`: its controls' values and which sound
/// and path of the library it plays (by name: "<scene>: <source>").
ViewSource describe_source(const LiveSession& session, std::size_t i) {
  const auto& s = session.scene().sources[i];
  const auto& lib = session.library();
  ViewSource v;
  v.name = s.name, v.gain_db = float(s.gain_db), v.rolloff = float(s.distance.rolloff);
  v.reference_distance = float(s.distance.reference_distance);
  v.distance_model = host::distance_model_index(s.distance.model);
  const std::string own = std::filesystem::path(session.scene_name()).stem().string() + ": " + s.name;
  for (std::size_t k = 0; k < lib.sound_names.size(); ++k)
    if (lib.sound_names[k] == own) v.sound = int(k);
  v.path_choice = s.path ? -1 : 0;  // -1: a path not in the list (a file loaded later)
  for (std::size_t k = 1; k < lib.path_names.size() && s.path; ++k)
    if (lib.path_names[k] == own) v.path_choice = int(k);
  return v;
}

/// The first 16 s of source `i`'s path, for drawing (empty: fixed).
std::vector<std::array<float, 3>> sample_path(const LiveSession& session, std::size_t i) {
  std::vector<std::array<float, 3>> r;
  if (const auto& path = session.scene().sources[i].path)
    for (int k = 0; k <= 64; ++k) {
      const auto x = scenes::path_position(*path, k * 0.25);
      r.push_back({float(x[0]), float(x[1]), float(x[2])});
    }
  return r;
}

}  // namespace

struct WindowView::Impl {
  std::unique_ptr<DemoWindow> win;
  WindowModel model;
  std::uint64_t generation = 0;
  Clock::time_point last_frame = Clock::now() - std::chrono::seconds(1);
  milliseconds last_frame_cost{0};
  std::vector<float> last_view;  ///< what view_changed saw last

  void describe(const LiveSession& session);
  [[nodiscard]] bool view_changed(const HeadPose& head, const EStrackerstate& ts, const EStrackerimage& im);
  void fill(const LiveSession& session, const OutputStats& stats, const HeadPose& head, double t);
  void fill_picture(const EStrackerimage& im);
  void apply(const WindowActions& act, LiveSession& session, double t);
  void apply_sources(const WindowActions& act, LiveSession& session, double t);
};

/// The window's view of the scene (after every load).
void WindowView::Impl::describe(const LiveSession& session) {
  generation = session.scene_generation();
  model.scene = session.scene_name(), model.room = session.scene().room;
  model.room_index = 0;
  for (std::size_t i = 0; i < model.rooms.size(); ++i)
    if (model.rooms[i] == model.room) model.room_index = int(i);
  model.scene_index = 0;
  for (std::size_t i = 0; i < model.scenes.size(); ++i)
    if (model.scenes[i] + ".json" == model.scene || model.scenes[i] == model.scene) model.scene_index = int(i);
  model.sources.clear();
  for (std::size_t i = 0; i < session.scene().sources.size(); ++i) {
    model.sources.push_back(describe_source(session, i));
    model.sources.back().path = sample_path(session, i);
  }
}

/// True when what the window shows moved since the last call (head, sources,
/// dots, the tracker's state, a new camera picture): frames of an unchanged
/// view are not drawn.
bool WindowView::Impl::view_changed(const HeadPose& head, const EStrackerstate& ts, const EStrackerimage& im) {
  const auto& p = head.position;
  const auto& q = head.orientation;
  std::vector<float> now{float(p[0]), float(p[1]), float(p[2]), float(q[0]), float(q[1]), float(q[2]), float(q[3]),
                         float(ts.state), float(ts.dot_count),
                         float(im.available), float(im.frame % 4096)};
  for (const auto& s : model.sources) now.insert(now.end(), s.position.begin(), s.position.end());
  for (ESuint i = 0; i < ts.dot_count && i < ES_TRACKER_MAX_DOTS; ++i) {
    now.push_back(ts.dots[i].x);
    now.push_back(ts.dots[i].y);
  }
  bool moved = now.size() != last_view.size();
  for (std::size_t i = 0; !moved && i < now.size(); ++i) moved = std::abs(now[i] - last_view[i]) > 1e-4f;
  last_view = std::move(now);
  return moved;
}

void WindowView::Impl::fill(const LiveSession& session, const OutputStats& stats, const HeadPose& head, double t) {
  const host::TrackerStatus& tracker = session.tracker();
  model.time_s = t, model.load = stats.load_last.load(), model.load_max = stats.load_max.load();
  model.xruns = stats.xruns.load(), model.blocks = stats.blocks.load();
  model.message = session.message();
  const auto& L = session.scene().listener.position;
  const auto& p = head.position;
  model.head_position = {float(p[0]) + float(L[0]), float(p[1]) + float(L[1]), float(p[2]) + float(L[2])};
  const auto& q = head.orientation;
  model.head_orientation = {float(q[0]), float(q[1]), float(q[2]), float(q[3])};
  model.tracker_state = tracker.state, model.tracker_message = tracker.message;
  model.tracker_alarm = tracker.alarm, model.tracker_rate = tracker.raw.rate_hz;
  model.tracker_frames = tracker.raw.frames;
  model.dots.clear();
  for (ESuint i = 0; i < tracker.raw.dot_count && i < ES_TRACKER_MAX_DOTS; ++i) {
    const EStrackerdot& d = tracker.raw.dots[i];
    model.dots.push_back({d.x, d.y, d.size, d.label});
  }
}

/// The camera's size and picture for the camera view; the picture is copied
/// only when its frame changed (the window uploads it then).
void WindowView::Impl::fill_picture(const EStrackerimage& im) {
  model.camera_width = im.camera_width > 0 ? int(im.camera_width) : ES_CAMERA_WIDTH;
  model.camera_height = im.camera_height > 0 ? int(im.camera_height) : ES_CAMERA_HEIGHT;
  if (!im.available || im.width == 0 || im.height == 0) {
    model.picture.clear();
    model.picture_width = model.picture_height = 0;
    return;
  }
  if (!model.picture.empty() && im.frame == model.picture_frame) return;
  model.picture_width = int(im.width), model.picture_height = int(im.height);
  model.picture.assign(im.pixels, im.pixels + std::size_t(im.width) * im.height);
  model.picture_frame = im.frame;
}

void WindowView::Impl::apply(const WindowActions& act, LiveSession& session, double t) {
  if (act.recenter) session.recenter();
  if (act.next_scene)
    session.next_scene(t);
  else if (act.scene_changed)
    session.pick_scene(std::size_t(model.scene_index), t);
  else if (act.load_file)
    session.load_scene_file(model.scene_file_input, t);
  if (session.scene_generation() != generation) describe(session);
  if (act.next_hrtf) session.next_hrtf();
  model.hrtf = session.hrtf_name();
  if (act.next_room)
    session.next_room();
  else if (act.room_changed)
    session.pick_room(std::size_t(model.room_index));
  model.room = session.scene().room;
  for (std::size_t i = 0; i < model.rooms.size(); ++i)
    if (model.rooms[i] == model.room) model.room_index = int(i);
  apply_sources(act, session, t);
}

/// The per-source controls: gain and distance, sound, path, position.
void WindowView::Impl::apply_sources(const WindowActions& act, LiveSession& session, double t) {
  const std::size_t n = model.sources.size();
  const auto& lib = session.library();
  auto& sources = session.sources();
  for (int i : act.changed_sources) {
    if (std::size_t(i) >= n) continue;
    const auto& v = model.sources[std::size_t(i)];
    const auto m = host::kDistanceModels[std::size_t(v.distance_model) % host::kDistanceModels.size()].model;
    sources.set_gain_distance(std::size_t(i), v.gain_db, m, v.rolloff, v.reference_distance);
  }
  for (int i : act.changed_sounds) {
    if (std::size_t(i) >= n) continue;
    const auto& v = model.sources[std::size_t(i)];
    if (v.sound < 0 || std::size_t(v.sound) >= lib.sounds.size()) continue;
    try {
      sources.set_sound(std::size_t(i), lib.sounds[std::size_t(v.sound)]);
    } catch (const std::exception& e) {
      session.say(e.what());
    }
  }
  for (int i : act.changed_paths) {
    if (std::size_t(i) >= n) continue;
    auto& v = model.sources[std::size_t(i)];
    if (v.path_choice < 0) continue;
    std::optional<scenes::MotionPath> path;
    if (v.path_choice > 0) path = lib.paths[std::size_t(v.path_choice) - 1];
    sources.set_path(std::size_t(i), std::move(path), t);
    v.path = sample_path(session, std::size_t(i));
  }
  for (int i : act.changed_positions)
    if (std::size_t(i) < n) sources.set_position(std::size_t(i), model.sources[std::size_t(i)].position);
}

std::unique_ptr<WindowView> WindowView::open(const LiveOptions& o, const LiveSession& session,
                                             const std::string& device, double latency_s) {
  if (!o.window || !(std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY"))) return nullptr;
  // The window's thread (this one, and the software rasteriser's threads it
  // starts) yields to the audio: it runs at a lower priority (nice 10) than
  // the audio thread PortAudio already started at the process's.
  // Mesa's software rasteriser draws on this thread alone (not on extra
  // threads of its own), unless the person chose otherwise: the window then
  // takes at most one core, and the other stays for the audio and the server.
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 10) != 0)
    std::fprintf(stderr, "earshot demo: could not lower the window thread's priority\n");
  setenv("LP_NUM_THREADS", "0", 0);
  auto impl = std::make_unique<Impl>();
  try {
    impl->win = std::make_unique<DemoWindow>("earshot demo");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "earshot demo: %s; status on the terminal instead\n", e.what());
    return nullptr;
  }
  if (impl->win->software())
    std::printf("  window: OpenGL in software (%s): %d frames/s at most, no anti-aliasing, "
                "drawn at a lower priority than the audio\n",
                impl->win->renderer().c_str(), kSoftwareFps);
  WindowModel& m = impl->model;
  m.device = device, m.latency_ms = latency_s * 1e3, m.tracker = session.tracker().spec;
  m.rooms = session.rooms();
  for (const auto& d : host::kDistanceModels) m.distance_models.emplace_back(d.name);
  m.sounds = session.library().sound_names, m.paths = session.library().path_names;
  m.scenes = session.scene_args();
  m.message = session.message();
  impl->describe(session);
  return std::unique_ptr<WindowView>(new WindowView(std::move(impl)));
}

bool WindowView::tick(LiveSession& session, const OutputStats& stats, const HeadPose& head, double t) {
  Impl& v = *impl_;
  if (session.scene_generation() != v.generation) v.describe(session);  // a key loaded another
  // 30 frames a second at most (software OpenGL: kSoftwareFps, and never
  // more than half of this thread's time), drawn at a lower priority than
  // the audio; nothing moved and nothing typed: 4 frames a second.
  const auto now = Clock::now();
  const auto gap = std::max(v.win->software() ? milliseconds(1000 / kSoftwareFps) : milliseconds(33),
                            2 * v.last_frame_cost);
  if (now - v.last_frame < gap) return true;
  for (std::size_t i = 0; i < v.model.sources.size(); ++i) {
    const auto x = session.sources().position(i, t);
    v.model.sources[i].position = {float(x[0]), float(x[1]), float(x[2])};
  }
  const EStrackerimage& picture = session.tracker_image();
  if (now - v.last_frame < milliseconds(250) && !v.view_changed(head, session.tracker().raw, picture)) return true;
  v.last_frame = now;
  v.fill(session, stats, head, t);
  v.fill_picture(picture);
  const WindowActions act = v.win->frame(v.model);
  v.last_frame_cost = std::chrono::duration_cast<milliseconds>(Clock::now() - now);
  if (act.quit) return false;
  v.apply(act, session, t);
  return true;
}

void WindowView::finish(const LiveOptions& o) {
  std::printf("  window: %ld frames drawn\n", impl_->win->frames());
  const WindowModel& m = impl_->model;
  if (impl_->win->pictures() > 0)
    std::printf("  window: %ld camera pictures shown (%d x %d of the camera's %d x %d)\n", impl_->win->pictures(),
                m.picture_width, m.picture_height, m.camera_width, m.camera_height);
  if (!o.screenshot.empty()) {
    impl_->win->screenshot(o.screenshot);
    std::printf("  screenshot %s\n", o.screenshot.c_str());
  }
}

#else  // a build without the window: the terminal's status line only

struct WindowView::Impl {};
std::unique_ptr<WindowView> WindowView::open(const LiveOptions&, const LiveSession&, const std::string&, double) {
  return nullptr;
}
bool WindowView::tick(LiveSession&, const OutputStats&, const HeadPose&, double) { return true; }
void WindowView::finish(const LiveOptions&) {}

#endif

WindowView::WindowView(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
WindowView::~WindowView() = default;

}  // namespace earshot::demo
