// A stereo WAV file written through libsndfile, closed on every way out.
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <vector>

namespace earshot::host {

enum class WavFormat { float32, pcm24 };

class WavWriter {
 public:
  /// Opens `path` for writing (no PEAK chunk: it carries a timestamp, and
  /// the same input must give the same bytes). Throws earshot::InputError
  /// naming the file when it cannot be written.
  WavWriter(const std::filesystem::path& path, int sample_rate, WavFormat format);
  ~WavWriter();
  WavWriter(const WavWriter&) = delete;
  WavWriter& operator=(const WavWriter&) = delete;

  /// Appends frames, interleaved left, right. Throws InputError on a failed write.
  void write_interleaved(std::span<const float> lr);
  /// Appends left.size() frames (right the same size).
  void write(std::span<const float> left, std::span<const float> right);
  /// Closes the file, which writes the header's final sizes; throws InputError
  /// if that fails (a full disk would leave a WAV that claims no frames).
  /// Without it the destructor closes and cannot report.
  void close();

 private:
  struct Close {
    void operator()(void* f) const;
  };
  std::filesystem::path path_;
  std::unique_ptr<void, Close> file_;  ///< SNDFILE*, kept out of this header
  std::vector<float> interleaved_;
};

}  // namespace earshot::host
