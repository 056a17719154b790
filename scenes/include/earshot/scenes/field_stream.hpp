// FieldStream: a bed's Ambisonic file (scene.hpp, SceneBed) read a block at
// a time: converted to ambiX (ACN, SN3D) as it is read
// (ambisonics/ambix_file.hpp: the order from the channel count, an error
// naming the file when the count is not (N+1)^2) and resampled to the
// scene's rate with libsamplerate (sinc, medium quality) when the file's
// differs, looping when the bed says so. A long file is never read whole.
//
// Not for the audio thread (it reads the file): a player reads ahead on
// its control thread (host/field_player.hpp).
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "earshot/audio/ambisonics/ambix_file.hpp"
#include "earshot/scenes/scene.hpp"

namespace earshot::scenes {

/// The convention a SceneBed names ("ambix", "n3d", "fuma").
[[nodiscard]] ambisonics::Convention bed_convention(const SceneBed& bed);

/// The scene `earshot render --ambix FILE` and `earshot demo --ambix FILE`
/// play: the file as one bed in `convention`, as long as the file, at its
/// rate, no room, no point sources. Throws InputError naming the file.
[[nodiscard]] Scene scene_of_field(const std::filesystem::path& file, const std::string& convention = "ambix");

class FieldStream {
 public:
  /// Throws earshot::InputError naming the file (missing, unreadable, not an
  /// Ambisonic channel count, cannot be resampled).
  FieldStream(const SceneBed& bed, double sample_rate);
  ~FieldStream();
  FieldStream(const FieldStream&) = delete;
  FieldStream& operator=(const FieldStream&) = delete;

  [[nodiscard]] int order() const { return order_; }
  [[nodiscard]] std::size_t channels() const { return channels_; }
  /// The file's own rate and length (frames at that rate).
  [[nodiscard]] double file_rate() const { return file_rate_; }
  [[nodiscard]] std::size_t file_frames() const { return file_frames_; }

  /// Up to `frames` frames at the scene's rate into `interleaved`
  /// (channels() per frame, ambiX); returns how many: fewer only once a
  /// bed that does not loop has ended (then 0 from there on).
  std::size_t read(std::span<float> interleaved, std::size_t frames);
  [[nodiscard]] bool ended() const { return ended_; }

 private:
  std::size_t fill_input();  // the next chunk of the file, interleaved, into in_
  void reopen();

  SceneBed bed_;
  double rate_;
  std::unique_ptr<ambisonics::AmbixReader> reader_;
  int order_ = 0;
  std::size_t channels_ = 0;
  double file_rate_ = 0;
  std::size_t file_frames_ = 0;
  struct Resampler;
  std::unique_ptr<Resampler> src_;  // null when the rates agree
  std::vector<float> planar_, in_;  // a chunk read; interleaved
  std::size_t in_frames_ = 0, in_used_ = 0;
  bool file_done_ = false, ended_ = false;
};

}  // namespace earshot::scenes
