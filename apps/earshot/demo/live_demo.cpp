// `earshot demo` in real time: the control thread's loop. The scene side is
// LiveSession (over host/), the audio thread's block render_block, the
// window WindowView; here are the terminal (keys, status line), the tracker's
// news and the recordings asked for (--capture, --capture-poses).
#include "live_demo.hpp"

#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <thread>

#include "audio_output.hpp"
#include "block_render.hpp"
#include "earshot/errors.hpp"
#include "earshot/geometry.hpp"
#include "earshot/host/wav_writer.hpp"
#include "earshot/scenes/field_stream.hpp"
#include "earshot/stop_signals.hpp"
#include "keys.hpp"
#include "live_session.hpp"
#include "window_view.hpp"

namespace earshot::demo {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

/// The head as the world's last block heard it (the C API hands it as floats).
HeadPose heard_head(ESworld world) {
  float p[3]{}, q[4]{1, 0, 0, 0};
  esGetHeadPose(world, p, q);
  HeadPose h;
  h.position = {p[0], p[1], p[2]};
  h.orientation = {q[0], q[1], q[2], q[3]};
  return h;
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

/// --capture-poses: the head's yaw per control tick, written as it comes
/// (the control thread's own file; nothing kept in memory).
class PoseLog {
 public:
  explicit PoseLog(const std::filesystem::path& path) {
    if (path.empty()) return;
    f_.open(path);
    if (!f_) throw InputError::at(path.string(), 0, "", "cannot write");
    f_ << "t,yaw_deg\n";
  }
  void add(double t, double yaw) {
    if (f_.is_open()) f_ << t << ',' << yaw << '\n';
  }

 private:
  std::ofstream f_;
};

/// What the tracker says goes to the terminal too, once per change: at once
/// when it is an alarm (no remote, disconnected), else once it held for half
/// a second (a frame or two of 'lost' is not news).
class TrackerNews {
 public:
  /// A tracker that failed to attach was said already.
  explicit TrackerNews(const host::TrackerStatus& t) {
    if (!t.failed.empty()) said_ = t.state + ": " + t.message;
  }
  void update(const host::TrackerStatus& t, Clock::time_point now, bool status_line) {
    const std::string news = t.state + ": " + t.message;
    if (news != pending_) pending_ = news, pending_since_ = now;
    if (t.message.empty() || news == said_ || !(t.alarm || now - pending_since_ >= milliseconds(500))) return;
    std::fprintf(stderr, "%searshot demo: tracker %s %s: %s\n", status_line ? "\n" : "", t.spec.c_str(),
                 t.state.c_str(), t.message.c_str());
    said_ = news;
  }

 private:
  std::string said_, pending_;
  Clock::time_point pending_since_ = Clock::now();
};

/// Stops the audio before the sounds it reads go (declared after the session).
struct StopAudio {
  AudioOutput& out;
  ~StopAudio() { out.stop(); }
};

/// A key typed on the terminal (keys.hpp). False: quit.
bool handle_key(char k, LiveSession& session, double t) {
  switch (k) {
    case 'q': case 'Q': case 27: return false;
    case 'r': case 'R': session.recenter(); break;
    case 'n': case 'N': session.next_scene(t); break;
    case 'm': case 'M': session.next_room(); break;
    case 'h': case 'H': session.next_hrtf(); break;
    default: break;
  }
  return true;
}

void print_status(double t, double yaw, const host::TrackerStatus& tracker, const OutputStats& st) {
  std::fprintf(stderr, "\r%6.1f s  yaw %+6.1f  tracker %s %3.0f Hz %u dots  load %4.1f%% (max %4.1f%%)  xruns %llu   ",
               t, yaw, tracker.state.c_str(), double(tracker.raw.rate_hz), tracker.raw.dot_count,
               100 * st.load_last.load(), 100 * st.load_max.load(), static_cast<unsigned long long>(st.xruns.load()));
}

/// Plays until the duration ends, 'q', the window closes or SIGINT / SIGTERM /
/// SIGHUP (then the captures are written as after 'q').
void control_loop(const LiveOptions& o, LiveSession& session, const OutputStats& st, WindowView* window,
                  PoseLog& poses) {
  const StopSignals stop;
  RawTerminal term;
  const bool status = isatty(STDERR_FILENO);
  session.refresh_tracker();
  TrackerNews news(session.tracker());
  auto last_tracker = Clock::now() - std::chrono::seconds(1), last_status = Clock::now();
  for (;;) {
    const double t = double(st.blocks.load()) * double(o.buffer) / session.rate();
    if (o.duration > 0 && t >= o.duration) break;
    if (stop.requested()) break;
    if (!handle_key(term.key(), session, t)) break;
    session.sources().move(t);
    const HeadPose head = heard_head(session.world());
    const double yaw = ypr_from_quat(head.orientation).yaw * 180.0 / std::numbers::pi;
    poses.add(t, yaw);
    const auto now = Clock::now();
    if (now - last_tracker >= milliseconds(100)) {
      last_tracker = now;
      session.refresh_tracker();
      news.update(session.tracker(), now, status);
    }
    if (window && !window->tick(session, st, head, t)) break;
    if (status && now - last_status > milliseconds(250)) {
      last_status = now;
      print_status(t, yaw, session.tracker(), st);
    }
    std::this_thread::sleep_for(milliseconds(5));
  }
  if (status) std::fputc('\n', stderr);
  if (stop.requested()) std::fprintf(stderr, "earshot demo: stopped by %s\n", StopSignals::name(stop.signal()));
}

void print_summary(const LiveSession& session, const OutputStats& st, unsigned long buffer) {
  const host::TrackerStatus& tracker = session.tracker();
  std::printf("  tracker %s: %s%s%s\n", tracker.spec.c_str(), tracker.state.c_str(),
              tracker.message.empty() ? "" : ": ", tracker.message.c_str());
  const double block_s = double(buffer) / session.rate();
  const auto blocks = st.blocks.load();
  const double mean = blocks ? st.load_sum.load() / double(blocks) : 0.0;
  std::printf("  played %.1f s: %llu blocks, %llu xruns, audio-thread load mean %.1f%% max %.1f%% of one core\n",
              double(blocks) * block_s, static_cast<unsigned long long>(blocks),
              static_cast<unsigned long long>(st.xruns.load()), 100 * mean, 100 * st.load_max.load());
  if (st.xruns.load() > 0)
    std::printf("  xruns between %.2f s and %.2f s\n", double(st.first_xrun_block.load()) * block_s,
                double(st.last_xrun_block.load()) * block_s);
}

}  // namespace

void list_devices() {
  AudioOutput out;
  std::printf("Output devices (* default):\n%s", describe_devices(out.devices()).c_str());
}

long run_live(const LiveOptions& o) {
  NamedScene first = load_demo_scene(o.scene, o.room);
  if (!o.ambix.empty()) {  // the field loops while the demo plays
    scenes::Scene field = scenes::scene_of_field(o.ambix);
    field.beds.front().loop = true;
    if (o.ambix_alone) first = {field, std::filesystem::path(o.ambix).filename().string(), ""};
    else first.scene.beds.push_back(field.beds.front());
  }
  AudioOutput out;
  const DeviceInfo dev = out.choose(o.device);  // none: NoDevice, and the caller renders instead
  LiveSession session(std::move(first), o);
  const double rate = session.rate();
  AudioSide side;
  side.world = session.world();
  if (!o.capture.empty())
    side.capture.assign(static_cast<std::size_t>(std::max(o.duration, 1.0) * rate + 2 * double(o.buffer)) * 2, 0.0f);
  PoseLog poses(o.capture_poses);

  out.start(dev, rate, o.buffer, &render_block, &side);
  StopAudio stop_audio{out};
  // The head prediction reaches to when a block is heard: the device's
  // output latency on top of the block itself.
  (void)esWorldi(session.world(), ES_OUTPUT_LATENCY_US,
                 static_cast<ESint>(std::lround(std::clamp(out.latency_s(), 0.0, 1.0) * 1e6)));
  // The audio thread real-time (when the server did not already and we may):
  // a window drawn in software next to it then cannot delay its blocks.
  const std::string rt_why = out.make_audio_thread_realtime();
  std::printf("earshot demo: playing %s (%zu sources, room %s) on '%s' (%s): %lu-frame buffer, "
              "output latency %.1f ms; tracker %s\n",
              session.scene_name().c_str(), session.scene().sources.size(), session.scene().room.c_str(),
              dev.name.c_str(), dev.host_api.c_str(), o.buffer, out.latency_s() * 1e3,
              session.tracker().spec.c_str());
  std::printf("  audio thread: %s\n", rt_why.empty() ? "real-time (SCHED_FIFO)" : rt_why.c_str());
  std::printf("Keys: %s\n", keys_line().c_str());
  std::fflush(stdout);

  const auto window = WindowView::open(o, session, dev.name, out.latency_s());
  control_loop(o, session, out.stats(), window.get(), poses);
  out.stop();
  if (window) window->finish(o);
  session.refresh_tracker();
  print_summary(session, out.stats(), o.buffer);
  if (!o.capture.empty()) {
    host::WavWriter(o.capture, static_cast<int>(rate), host::WavFormat::float32)
        .write_interleaved({side.capture.data(), side.captured.load()});
    std::printf("  captured %s\n", o.capture.c_str());
  }
  return static_cast<long>(out.stats().xruns.load());
}

}  // namespace earshot::demo
