#include "earshot/host/scene_sources.hpp"

#include <algorithm>
#include <cmath>

#include "earshot/host/distance_models.hpp"

namespace earshot::host {
namespace {

float db(double x) { return static_cast<float>(std::pow(10.0, x / 20.0)); }

/// The callback source: the scene's generator fills the block on the audio thread.
void pull(void* user, float* out, ESuint frames) {
  static_cast<scenes::SignalSource*>(user)->generate(std::span<float>(out, frames));
}

}  // namespace

SceneSources::SceneSources(const WorldHandle& world, double sample_rate) : world_(world), rate_(sample_rate) {}

SceneSources::~SceneSources() { delete_sources(); }

void SceneSources::delete_sources() {
  for (ESsource id : ids_) (void)esDeleteSource(world_.id(), id);
  ids_.clear();
  for (ESsource id : bed_ids_) (void)esDeleteSource(world_.id(), id);
  bed_ids_.clear();
}

std::string SceneSources::field(std::size_t i, const char* name) const {
  std::string f = "sources[" + std::to_string(i) + "]";
  if (*name) f += std::string(".") + name;
  return f;
}

void SceneSources::load(scenes::Scene scene) {
  std::vector<std::unique_ptr<scenes::SignalSource>> made;
  for (const auto& s : scene.sources) made.push_back(std::make_unique<scenes::SignalSource>(s.signal, rate_));
  // Beds read ahead half a second (at least two blocks of any size).
  std::vector<std::unique_ptr<FieldPlayer>> players;
  for (const auto& b : scene.beds) players.push_back(std::make_unique<FieldPlayer>(b, rate_, std::size_t(rate_ / 2) + 16384));
  delete_sources();
  for (auto& old : sounds_) retired_.push_back(std::move(old));
  for (auto& old : players_) retired_players_.push_back(std::move(old));
  sounds_ = std::move(made);
  players_ = std::move(players);
  scene_ = std::move(scene);
  origin_ = scene_.origin.empty() ? "scene" : scene_.origin;
  const auto& L = scene_.listener.position;
  world_.check(esListener3f(world_.id(), ES_POSITION, float(L[0]), float(L[1]), float(L[2])), origin_, "listener");
  set_room(scene_.room);
  for (std::size_t i = 0; i < scene_.sources.size(); ++i) add_source(i);
  for (std::size_t i = 0; i < scene_.beds.size(); ++i) add_bed(i);
  t0_ = -1;  // paths start again at the next move()
}

void SceneSources::add_bed(std::size_t i) {
  const ESworld w = world_.id();
  const scenes::SceneBed& b = scene_.beds[i];
  const std::string f = "beds[" + std::to_string(i) + "]";
  ESsource id = 0;
  world_.check(esCreateSource(w, &id), origin_, f);
  bed_ids_.push_back(id);
  FieldPlayer& p = *players_[i];
  // Designs (or reads) the decoder for the bed's order: the first of an order may take a moment.
  world_.check(esSourceAmbisonicCallback(w, id, static_cast<ESuint>(p.order()), &FieldPlayer::pull, &p), origin_, f);
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const Quat q = quat_from_ypr(b.yaw_deg * kDeg, b.pitch_deg * kDeg, b.roll_deg * kDeg);
  const float qv[4] = {float(q[0]), float(q[1]), float(q[2]), float(q[3])};
  world_.check(esSourcefv(w, id, ES_ORIENTATION_QUAT, qv), origin_, f + ".yaw_deg");
  world_.check(esSourcef(w, id, ES_GAIN, db(b.gain_db)), origin_, f + ".gain_db");
  world_.check(esSourcePlay(w, id), origin_, f);
}

void SceneSources::add_source(std::size_t i) {
  const ESworld w = world_.id();
  const scenes::SceneSource& s = scene_.sources[i];
  ESsource id = 0;
  world_.check(esCreateSource(w, &id), origin_, field(i, ""));
  ids_.push_back(id);
  const auto set = [&](ESenum param, float v, const char* name) {
    world_.check(esSourcef(w, id, param, v), origin_, field(i, name));
  };
  const auto x = scenes::source_position(s, 0.0);
  world_.check(esSource3f(w, id, ES_POSITION, float(x[0]), float(x[1]), float(x[2])), origin_, field(i, "position"));
  set(ES_GAIN, db(s.gain_db), "gain_db");
  world_.check(esSourcei(w, id, ES_DISTANCE_MODEL, es_distance_model(s.distance.model)), origin_,
               field(i, "distance_model"));
  set(ES_REFERENCE_DISTANCE, float(s.distance.reference_distance), "reference_distance");
  set(ES_ROLLOFF_FACTOR, float(s.distance.rolloff), "rolloff");
  // A float holds at most ~3.4e38: larger is "no limit" as well.
  set(ES_MAX_DISTANCE, float(std::min(s.distance.max_distance, 3.0e38)), "max_distance");
  set(ES_REVERB_SEND, s.reverb_send_db <= -120 ? 0.0f : db(s.reverb_send_db), "reverb_send_db");
  set(ES_AIR_ABSORPTION_FACTOR, float(s.air_absorption), "air_absorption");
  world_.check(esSourceCallback(w, id, &pull, sounds_[i].get()), origin_, field(i, "signal"));
  world_.check(esSourcePlay(w, id), origin_, field(i, ""));
}

void SceneSources::set_room(const std::string& room) {
  const ESworld w = world_.id();
  if (room != "none") world_.check(esReverbPreset(w, room.c_str()), origin_, "room");
  world_.check(esReverbi(w, ES_REVERB_ENABLED, room != "none" ? ES_TRUE : ES_FALSE), origin_, "room");
  scene_.room = room;
}

void SceneSources::move(double t) {
  if (t0_ < 0) t0_ = t;
  for (auto& p : players_) p->pump();  // the beds' files, read ahead of the audio thread
  for (std::size_t i = 0; i < ids_.size(); ++i)
    if (scene_.sources[i].path) {
      // The path's position at the block's start; the renderer glides the
      // propagation delay across the block, so Doppler follows.
      const auto x = position(i, t);
      world_.check(esSource3f(world_.id(), ids_[i], ES_POSITION, float(x[0]), float(x[1]), float(x[2])), origin_,
                   field(i, "path"));
    }
}

Vec3 SceneSources::position(std::size_t i, double t) const {
  return scenes::source_position(scene_.sources[i], std::max(0.0, t - std::max(t0_, 0.0)));
}

void SceneSources::set_sound(std::size_t i, const scenes::Signal& sig) {
  auto made = std::make_unique<scenes::SignalSource>(sig, rate_);  // may throw: nothing changed
  world_.check(esSourceCallback(world_.id(), ids_[i], &pull, made.get()), origin_, field(i, "signal"));
  retired_.push_back(std::move(sounds_[i]));
  sounds_[i] = std::move(made);
  scene_.sources[i].signal = sig;
}

void SceneSources::set_path(std::size_t i, std::optional<scenes::MotionPath> path, double t) {
  if (!path) scene_.sources[i].position = position(i, t);  // stays where it is
  scene_.sources[i].path = std::move(path);
  move(t);
}

void SceneSources::set_position(std::size_t i, const std::array<float, 3>& p) {
  scene_.sources[i].path.reset();
  scene_.sources[i].position = {p[0], p[1], p[2]};
  world_.check(esSource3f(world_.id(), ids_[i], ES_POSITION, p[0], p[1], p[2]), origin_, field(i, "position"));
}

void SceneSources::set_gain_distance(std::size_t i, double gain_db, audio::DistanceModel model, double rolloff,
                                     double reference_distance) {
  const ESworld w = world_.id();
  auto& d = scene_.sources[i].distance;
  world_.check(esSourcef(w, ids_[i], ES_GAIN, db(gain_db)), origin_, field(i, "gain_db"));
  world_.check(esSourcei(w, ids_[i], ES_DISTANCE_MODEL, es_distance_model(model)), origin_,
               field(i, "distance_model"));
  world_.check(esSourcef(w, ids_[i], ES_ROLLOFF_FACTOR, float(rolloff)), origin_, field(i, "rolloff"));
  world_.check(esSourcef(w, ids_[i], ES_REFERENCE_DISTANCE, float(reference_distance)), origin_,
               field(i, "reference_distance"));
  scene_.sources[i].gain_db = gain_db;
  d.model = model, d.rolloff = rolloff, d.reference_distance = reference_distance;
}

}  // namespace earshot::host
