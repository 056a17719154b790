// Reading Ambisonic files through libsndfile (WAV, W64, CAF, and whatever
// else it opens): the order from the channel count, the signal converted to
// ambiX (ACN, SN3D) as it is read.
//
// A file holds (N+1)^2 channels for order N (ambiX, N3D), or 4, 9 or 16 for
// FuMa orders 1..3 (mixed-order FuMa layouts are not read). Anything else is
// an earshot::InputError naming the file and the count, e.g.
//   "bed.wav: field 'channels': 5 channels is not an Ambisonic signal (4, 9, 16, 25, 36, 49 or 64: (N + 1)^2)".
// Errors opening or reading the file name it too.
//
// AmbixReader streams (a long bed never has to fit in memory): read() gives
// the next frames planar, as the DSP units take them. Not for the audio
// thread (it does I/O); a player reads ahead on another thread.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"

namespace earshot::ambisonics {

class AmbixReader {
 public:
  /// Opens `path`; `convention` is what the file holds (ambiX unless told).
  explicit AmbixReader(const std::filesystem::path& path, Convention convention = Convention::ambix);
  ~AmbixReader();
  AmbixReader(AmbixReader&&) noexcept;
  AmbixReader& operator=(AmbixReader&&) noexcept;

  [[nodiscard]] int order() const { return order_; }
  [[nodiscard]] std::size_t channels() const { return channel_count(order_); }
  [[nodiscard]] double sample_rate() const { return rate_; }
  /// Frames in the file.
  [[nodiscard]] std::size_t frames() const { return frames_; }

  /// Reads up to `frames` frames into `out` (channels() x frames planar,
  /// ambiX); returns how many were read (0 at the end). Frames past the end
  /// of the file are zeroed.
  std::size_t read(std::span<float> out, std::size_t frames);

 private:
  struct File;
  std::filesystem::path path_;
  std::unique_ptr<File> file_;
  int order_ = 0;
  double rate_ = 0.0;
  std::size_t frames_ = 0;
  ChannelMap map_;
  std::vector<float> interleaved_;
};

/// A whole file, converted: channels() x frames planar.
struct AmbixSignal {
  int order = 0;
  double sample_rate = 0.0;
  std::size_t frames = 0;
  std::vector<float> samples;
  [[nodiscard]] std::span<const float> channel(std::size_t c) const {
    return std::span<const float>(samples).subspan(c * frames, frames);
  }
};
[[nodiscard]] AmbixSignal read_ambix(const std::filesystem::path& path, Convention convention = Convention::ambix);

}  // namespace earshot::ambisonics
