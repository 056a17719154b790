// A scene's sources and room in a plugin world: each source a callback
// source fed by the scene's generator (scenes::SignalSource, run inside
// esRender on the audio thread), with the scene's gain, distance model and
// sends, moved along its path by move() -- once per block offline, once per
// control tick live. The scene's Ambisonic beds are field sources
// (esSourceAmbisonicCallback) fed by FieldPlayers (field_player.hpp), read
// ahead by move(). Everything here runs on the world's control thread.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "earshot/audio/distance_model.hpp"
#include "earshot/host/field_player.hpp"
#include "earshot/host/world_handle.hpp"
#include "earshot/scenes/motion_path.hpp"
#include "earshot/scenes/scene.hpp"
#include "earshot/scenes/signal_source.hpp"

namespace earshot::host {

class SceneSources {
 public:
  /// Sources go into `world`, which must outlive this; sounds are made at
  /// `sample_rate` (the world's).
  SceneSources(const WorldHandle& world, double sample_rate);
  /// Deletes the sources. Destroy it only once nothing renders the world:
  /// the audio thread may be inside a sound (live hosts stop the audio first).
  ~SceneSources();
  SceneSources(const SceneSources&) = delete;
  SceneSources& operator=(const SceneSources&) = delete;

  /// Replaces the sources, the room and the listener's position by the
  /// scene's (its orientation is left to listener.hpp or a tracker). The
  /// sounds are made first: a file that cannot be read throws before
  /// anything changes. Errors name the scene's file and field, e.g.
  /// "scene.json: field 'sources[2].gain_db': ...".
  void load(scenes::Scene scene);
  /// "none" or a room preset (esReverbPreset's names).
  void set_room(const std::string& room);

  /// Moves the sources on paths to where they are `t` seconds after the
  /// first move() since load() (offline: t is the block's start, from 0).
  void move(double t);
  /// Where source `i` is at `t` (the clock of move()).
  [[nodiscard]] Vec3 position(std::size_t i, double t) const;

  // Live edits of source `i` (a host's controls).
  /// A new sound; throws (changing nothing) when it cannot be made.
  void set_sound(std::size_t i, const scenes::Signal& sig);
  /// A path, or none: the source then stays where it is at `t`.
  void set_path(std::size_t i, std::optional<scenes::MotionPath> path, double t);
  /// A fixed position (the path goes).
  void set_position(std::size_t i, const std::array<float, 3>& p);
  void set_gain_distance(std::size_t i, double gain_db, audio::DistanceModel model, double rolloff,
                         double reference_distance);

  [[nodiscard]] const scenes::Scene& scene() const { return scene_; }
  [[nodiscard]] std::size_t size() const { return ids_.size(); }
  /// The beds' sources and players (in the scene's order).
  [[nodiscard]] std::size_t bed_count() const { return bed_ids_.size(); }
  [[nodiscard]] ESsource bed_id(std::size_t i) const { return bed_ids_[i]; }
  [[nodiscard]] const FieldPlayer& bed_player(std::size_t i) const { return *players_[i]; }
  /// The plugin's handle of source `i` (for a host's own calls).
  [[nodiscard]] ESsource id(std::size_t i) const { return ids_[i]; }

 private:
  [[nodiscard]] std::string field(std::size_t i, const char* name) const;
  void add_source(std::size_t i);
  void add_bed(std::size_t i);
  void delete_sources();

  const WorldHandle& world_;
  double rate_;
  double t0_ = -1;  ///< the clock of move() at its first call since load(); < 0: not yet
  scenes::Scene scene_;
  std::string origin_ = "scene";
  std::vector<ESsource> ids_;
  // Sounds replaced or dropped are kept (retired) until destruction: the
  // audio thread may still be inside one when its source changes.
  std::vector<std::unique_ptr<scenes::SignalSource>> sounds_, retired_;
  std::vector<ESsource> bed_ids_;
  std::vector<std::unique_ptr<FieldPlayer>> players_, retired_players_;
};

}  // namespace earshot::host
