// `earshot track live` and `earshot track record`: the live tracker from the
// command line. `live` runs the tracker thread on a source and prints the
// pose and state as they change (one updating line on a terminal, plain
// lines otherwise), optionally recording one row per tracker frame (pose
// and state) as a Pose track CSV for `earshot render --pose-track`, with
// --record-camera the beacon's absolute pose in the camera frame, and sending
// the poses on to other programs (--send: OSC for SPARTA, IEM or Earshot,
// opentrack's packet); `record` writes a camera source's raw dots as a Dots
// CSV for `track solve` or `--source replay:`.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "earshot/errors.hpp"
#include "earshot/geometry.hpp"
#include "earshot/pose_slot.hpp"
#include "earshot/stop_signals.hpp"
#include "earshot/tracker/core/led_model.hpp"
#include "earshot/tracker/live/live_tracker.hpp"
#include "earshot/pose_track_csv.hpp"
#include "earshot/tracker/live/source_spec.hpp"
#include "earshot/tracker/send/send_spec.hpp"
#include "track_commands.hpp"

namespace earshot::app {
namespace {

using namespace earshot::tracker;
using clock = std::chrono::steady_clock;

struct LiveOptions {
  std::string source = "wiimote";
  std::string record;
  std::string record_camera;  // live: the beacon's absolute pose in the camera frame, per frame
  std::string out;
  double duration_s = 0.0;  // 0: until Ctrl-C (or SIGTERM, SIGHUP) or the source ends
  bool fast = false;
  double focal = 1280.0;
  std::string model_path;
  std::string filter = "eskf";
  std::string listen;  // live: the pose source's listen address (empty: the spec's, 127.0.0.1 by default)
  std::vector<std::string> send;  // live: where to send the poses (tracker/send/send_spec.hpp)
};

std::unique_ptr<FrameSource> make_source(const LiveOptions& o, bool camera_only) {
  const std::string text = o.listen.empty() ? o.source : with_listen_address(o.source, o.listen, "--source", "--listen");
  const SourceSpec spec = parse_source_spec(text, "--source");
  if (camera_only && spec.sends_poses())
    throw InputError::at("--source", 0, "", "'" + o.source + "' sends poses, not dots: record needs wiimote, sim or replay:FILE");
  SourceOptions so;
  so.pacing = o.fast ? Pacing::as_fast_as_possible : Pacing::real_time;
  so.camera = Camera::with_focal(o.focal);
  if (spec.kind == SourceSpec::Kind::sim && !o.model_path.empty()) so.model = load_led_model(o.model_path);
  return make_frame_source(spec, so);
}

std::string pose_line(const HeadPose& p, const LiveTracker::Status& st) {
  constexpr double deg = 180.0 / std::numbers::pi;
  const YawPitchRoll a = ypr_from_quat(p.orientation);
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "t=%8.2fs %-9s x=%+6.3f y=%+6.3f z=%+6.3f m  yaw=%+6.1f pitch=%+6.1f roll=%+6.1f deg  frames=%llu dropped=%llu",
                p.t, pose_state_name(p.state).data(), p.position[0], p.position[1], p.position[2], a.yaw * deg, a.pitch * deg, a.roll * deg,
                static_cast<unsigned long long>(st.frames), static_cast<unsigned long long>(st.dropped));
  return buf;
}

/// The beacon's pose in the camera frame (mm, x right, y down, z along the
/// optical axis) as a Pose track row: metres and a unit quaternion in the
/// same axes, with the frame's time and state.
HeadPose camera_row(const LiveTracker::FrameRow& row) {
  HeadPose h;
  h.t = row.listener.t;
  h.state = row.listener.state;
  const Pose& p = *row.camera;
  h.position = {p.t.x() * 1e-3, p.t.y() * 1e-3, p.t.z() * 1e-3};
  h.orientation = to_common(p.quaternion());
  return h;
}

void run_live(const LiveOptions& o) {
  // Recordings: one row per tracker frame from the first (camera frames, or
  // poses from a source that solves its own), with the state; notes make no
  // row. --record-camera: the same frames' beacon pose in the camera frame,
  // absolute (not relative to the recentred reference), from the first
  // frame the tracker has a pose for.
  std::ofstream file, camera_file;
  std::optional<PoseTrackCsvWriter> writer, camera_writer;
  if (!o.record.empty()) {
    file.open(o.record);
    if (!file) throw InputError::at(o.record, 0, "", "cannot create file");
    writer.emplace(file, true);
  }
  if (!o.record_camera.empty()) {
    camera_file.open(o.record_camera);
    if (!camera_file) throw InputError::at(o.record_camera, 0, "", "cannot create file");
    camera_writer.emplace(camera_file, true);
  }
  LiveConfig cfg;
  cfg.camera = Camera::with_focal(o.focal);
  const auto filter = filter_kind_from(o.filter);
  if (!filter) throw InputError::at("--filter", 0, "", "unknown filter '" + o.filter + "' (none, one-euro, median5, eskf)");
  cfg.tracker.filter = *filter;
  if (!o.model_path.empty()) cfg.model = load_led_model(o.model_path);
  for (const std::string& spec : o.send) cfg.send.push_back(parse_send_spec(spec, "--send"));
  PoseSlot slot;
  const bool tty = ::isatty(::fileno(stdout)) != 0;
  // SIGINT, SIGTERM and SIGHUP end the loop below; the tracker thread is then
  // joined, so the last row is whole, and the file is flushed and closed.
  const StopSignals stop;
  LiveTracker::Status st;
  std::string last_note;
  std::uint64_t rows = 0;  // written by the tracker thread; read after it is joined
  std::string sent;        // what the senders did, one line each
  {
    LiveTracker::FrameCallback on_frame;
    if (writer || camera_writer)
      on_frame = [&writer, &camera_writer, &rows](const LiveTracker::FrameRow& row) {
        if (writer && writer->write(row.listener)) ++rows;
        if (camera_writer && row.camera) camera_writer->write(camera_row(row));
      };
    LiveTracker tracker(make_source(o, false), slot, cfg, {}, std::move(on_frame));
    std::fprintf(stderr, "earshot: tracking from %s%s\n", tracker.status().source.c_str(),
                 tty ? " (Ctrl-C to stop)" : "");
    for (const auto& s : tracker.senders().senders()) std::fprintf(stderr, "earshot: sending poses to %s\n", s->describe().c_str());
    const auto start = clock::now();
    const auto period = std::chrono::milliseconds(tty ? 50 : 100);
    while (tracker.running() && !stop.requested()) {
      std::this_thread::sleep_for(period);
      if (o.duration_s > 0 && std::chrono::duration<double>(clock::now() - start).count() >= o.duration_s) break;
      st = tracker.status();
      if (!st.note.empty() && st.note != last_note) {
        std::fprintf(stdout, "%s%s\n", tty ? "\r\033[K" : "", st.note.c_str());
        last_note = st.note;
      }
      const HeadPose p = slot.load();
      if (p.sequence == 0) continue;
      if (tty) std::fprintf(stdout, "\r\033[K%s", pose_line(p, st).c_str());
      else std::fprintf(stdout, "%s\n", pose_line(p, st).c_str());
      std::fflush(stdout);
    }
    tracker.stop();
    st = tracker.status();
    sent = tracker.senders().summary();
  }
  if (tty) std::fprintf(stdout, "\n");
  if (stop.requested()) std::fprintf(stderr, "earshot: stopped by %s\n", StopSignals::name(stop.signal()));
  if (writer) {
    file.close();
    if (!file) throw InputError::at(o.record, 0, "", "write failed");
    std::fprintf(stderr, "earshot: recorded %llu frames to %s\n", static_cast<unsigned long long>(rows),
                 o.record.c_str());
  }
  if (camera_writer) {
    camera_file.close();
    if (!camera_file) throw InputError::at(o.record_camera, 0, "", "write failed");
  }
  for (std::size_t at = 0, nl; (nl = sent.find('\n', at)) != std::string::npos; at = nl + 1)
    std::fprintf(stderr, "earshot: %s\n", sent.substr(at, nl - at).c_str());
  if (!st.error.empty()) throw std::runtime_error(st.source + ": " + st.error);
  std::fprintf(stderr, "earshot: %llu frames, %llu poses published, %llu malformed inputs dropped, %llu impossible dots rejected\n",
               static_cast<unsigned long long>(st.frames), static_cast<unsigned long long>(st.published),
               static_cast<unsigned long long>(st.dropped), static_cast<unsigned long long>(st.rejected_dots));
}

void run_record(const LiveOptions& o) {
  const auto source = make_source(o, true);
  std::ofstream file(o.out);
  if (!file) throw InputError::at(o.out, 0, "", "cannot create file");
  DotsCsvWriter writer(file, false);
  const StopSignals stop;  // as in run_live: a signal ends the loop between frames
  const auto start = clock::now();
  long frames = 0;
  while (!stop.requested()) {
    if (o.duration_s > 0 && std::chrono::duration<double>(clock::now() - start).count() >= o.duration_s) break;
    const SourceEvent e = source->next(std::chrono::milliseconds(50));
    if (const auto* f = std::get_if<CameraFrame>(&e)) {
      writer.write(f->dots);
      ++frames;
    } else if (const auto* n = std::get_if<SourceNote>(&e)) {
      if (n->kind == SourceNote::Kind::ended) break;
      if (!n->message.empty()) std::fprintf(stderr, "earshot: %s\n", n->message.c_str());
    }
  }
  if (stop.requested()) std::fprintf(stderr, "earshot: stopped by %s\n", StopSignals::name(stop.signal()));
  file.close();
  if (!file) throw InputError::at(o.out, 0, "", "write failed");
  std::fprintf(stderr, "earshot: recorded %ld frames from %s to %s (%llu malformed reports dropped)\n", frames,
               source->describe().c_str(), o.out.c_str(), static_cast<unsigned long long>(source->dropped()));
}

void add_common(CLI::App& cmd, LiveOptions& o) {
  cmd.add_option("--duration", o.duration_s,
                 "Stop after this many seconds (default: until Ctrl-C, SIGTERM or SIGHUP, or the source ends)")
      ->check(CLI::NonNegativeNumber);
  cmd.add_flag("--fast", o.fast, "sim and replay: as fast as possible instead of in real time");
  cmd.add_option("--focal", o.focal, "Camera focal length in pixels (1024x768 image)")->capture_default_str()->check(CLI::PositiveNumber);
  cmd.add_option("--model", o.model_path, "Model JSON with the beacon's LED positions (default: thesis beacon)");
}

}  // namespace

void add_track_live_commands(CLI::App& track) {
  auto lo = std::make_shared<LiveOptions>();
  auto* live = track.add_subcommand("live", "Track live and print the listener pose and state; optionally record it as a Pose track CSV");
  live->add_option("--source,-s", lo->source, "Input: " + std::string(kSourceSpecs))->capture_default_str();
  live->add_option("--listen", lo->listen,
                   "Pose sources (opentrack, osc): the IPv4 address to listen on (default 127.0.0.1; 0.0.0.0 for every "
                   "interface: anyone on the network could then turn your head)");
  live->add_option("--filter", lo->filter, "Pose filter for camera sources: eskf (Kalman, default), one-euro, median5, none")
      ->capture_default_str();
  live->add_option("--record", lo->record,
                   "Write one row per tracker frame from the first, the listener pose and the tracker's state, as a "
                   "Pose track CSV (t_s,x_m,y_m,z_m,qw,qx,qy,qz,state)");
  live->add_option("--record-camera", lo->record_camera,
                   "Also write each frame's absolute beacon pose in the camera frame (x right, y down, z along the "
                   "optical axis; metres) with the state, in the same columns");
  live->add_option("--send", lo->send,
                   "Send every pose on (repeatable): " + std::string(kSendSpecs) +
                       "; 127.0.0.1 unless a host is named, at most rate (100) poses a second (docs/OSC.md)");
  add_common(*live, *lo);
  live->callback([lo] { run_live(*lo); });

  auto ro = std::make_shared<LiveOptions>();
  auto* rec = track.add_subcommand("record", "Record a camera source's dots (e.g. a real Wii Remote) as a Dots CSV");
  rec->add_option("--source,-s", ro->source, "Input: wiimote, sim, replay:FILE, webcam[:DEVICE][,OPTION=VALUE...]")->capture_default_str();
  rec->add_option("--out,-o", ro->out, "Dots CSV to write")->required();
  add_common(*rec, *ro);
  rec->callback([ro] { run_record(*ro); });
}

}  // namespace earshot::app
