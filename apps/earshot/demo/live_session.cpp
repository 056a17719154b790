#include "live_session.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "earshot/errors.hpp"
#include "earshot/host/rooms.hpp"
#include "earshot/scenes/presets.hpp"

namespace earshot::demo {
namespace {

NamedScene read_scene(const std::string& arg) {
  const auto file = scenes::resolve_scene_argument(arg);
  return {scenes::load_scene(file), file.filename().string(), ""};
}

std::string stem(const std::string& file_name) { return std::filesystem::path(file_name).stem().string(); }

ESworldparams world_params(const scenes::Scene& scene, const LiveOptions& o) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  p.sample_rate = static_cast<ESuint>(scene.sample_rate);
  p.block_size = static_cast<ESuint>(o.buffer);
  p.max_sources = 64;  // room for any scene picked later
  if (scene.listener.head_radius_m) p.head_radius_m = static_cast<float>(*scene.listener.head_radius_m);
  if (!o.hrtfs.empty() && !o.hrtfs.front().empty()) p.hrtf_path = o.hrtfs.front().c_str();
  return p;
}

}  // namespace

NamedScene load_demo_scene(const std::string& arg, const std::string& room) {
  NamedScene s;
  try {
    s = read_scene(arg);
  } catch (const InputError& e) {
    const std::string error = std::string(e.what()) + " -- playing circles instead";
    std::fprintf(stderr, "earshot demo: %s\n", error.c_str());
    s = read_scene("circles");
    s.error = error;
  }
  if (!room.empty()) s.scene.room = scenes::checked_room_name(room, "--room");
  return s;
}

void Library::add(const std::string& scene_name, const scenes::Scene& s) {
  for (const auto& src : s.sources) {
    sound_names.push_back(scene_name + ": " + src.name);
    sounds.push_back(src.signal);
    if (src.path) {
      path_names.push_back(scene_name + ": " + src.name);
      paths.push_back(*src.path);
    }
  }
}

LiveSession::LiveSession(NamedScene first, const LiveOptions& o)
    : world_(world_params(first.scene, o)),
      rate_(first.scene.sample_rate),
      sources_(world_, rate_),
      scene_name_(first.name),
      message_(first.error),
      scene_args_(scenes::preset_names()),
      rooms_(host::room_names()),
      hrtfs_(o.hrtfs.empty() ? std::vector<std::string>{""} : o.hrtfs) {
  // What can be picked: the presets (and the file given), their sounds and paths.
  lib_.add(stem(scene_name_), first.scene);
  for (const auto& name : scene_args_) {
    if (name + ".json" == scene_name_) continue;
    try {
      lib_.add(name, read_scene(name).scene);
    } catch (const std::exception&) {
      // a preset that does not load is simply not offered
    }
  }
  if (std::find(scene_args_.begin(), scene_args_.end(), stem(scene_name_)) == scene_args_.end() &&
      first.error.empty())
    scene_args_.push_back(o.scene);  // the file given on the command line
  for (std::size_t i = 0; i < scene_args_.size(); ++i)
    if (scene_args_[i] + ".json" == scene_name_) scene_pick_ = i;
  for (std::size_t i = 0; i < rooms_.size(); ++i)
    if (rooms_[i] == first.scene.room) room_pick_ = i;
  sources_.load(std::move(first.scene));

  tracker_ = host::attach_tracker(world_.id(), o.tracker, o.send);
  if (!tracker_.failed.empty())
    std::fprintf(stderr, "earshot demo: tracker %s failed: %s; the head is held straight\n", o.tracker.c_str(),
                 tracker_.failed.c_str());
}

const EStrackerimage& LiveSession::tracker_image() {
  if (!image_) image_ = std::make_unique<EStrackerimage>();
  image_->size = sizeof(EStrackerimage);
  if (esGetTrackerImage(world_.id(), image_.get()) != ES_OK) {
    image_->available = ES_FALSE;  // the view then shows the dots alone, as for a Wii Remote
    image_->camera_width = image_->camera_height = 0;
  }
  return *image_;
}

void LiveSession::say(const std::string& m) {
  std::fprintf(stderr, "%searshot demo: %s\n", isatty(STDERR_FILENO) ? "\n" : "", m.c_str());
  message_ = m;
}

void LiveSession::load_scene_file(const std::string& arg, double t) {
  try {
    NamedScene next = read_scene(arg);
    sources_.load(std::move(next.scene));
    sources_.move(t);
    scene_name_ = next.name;
    ++generation_;
    say("scene " + scene_name_ + " (" + std::to_string(scene().sources.size()) + " sources, room " + scene().room +
        ")");
  } catch (const std::exception& e) {
    say(std::string(e.what()) + " -- still playing " + scene_name_);
  }
}

void LiveSession::pick_scene(std::size_t i, double t) {
  if (scene_args_.empty()) return;
  scene_pick_ = i % scene_args_.size();
  load_scene_file(scene_args_[scene_pick_], t);
}

void LiveSession::next_scene(double t) { pick_scene(scene_pick_ + 1, t); }

std::string LiveSession::hrtf_name() const {
  const std::string& p = hrtfs_[hrtf_pick_];
  return p.empty() ? "MIT KEMAR" : std::filesystem::path(p).filename().string();
}

void LiveSession::next_hrtf() {
  if (hrtfs_.size() < 2) {
    say("HRTF " + hrtf_name() + ": the only set (give more with --hrtf A.sofa --hrtf B.sofa)");
    return;
  }
  const std::size_t next = (hrtf_pick_ + 1) % hrtfs_.size();
  const std::string& p = hrtfs_[next];
  // Prepared here (the control thread), crossfaded in by the audio thread.
  if (esWorldHrtf(world_.id(), p.empty() ? nullptr : p.c_str()) != ES_OK) {
    say(std::string("HRTF not changed: ") + esGetErrorMessage(world_.id()));
    return;
  }
  hrtf_pick_ = next;
  say("HRTF " + hrtf_name());
}

void LiveSession::pick_room(std::size_t i) {
  room_pick_ = i % rooms_.size();
  try {
    sources_.set_room(rooms_[room_pick_]);
    say("room " + rooms_[room_pick_]);
  } catch (const std::exception& e) {
    say(e.what());
  }
}

}  // namespace earshot::demo
