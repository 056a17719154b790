// YUV4MPEG2 files of 8-bit grey frames: the layout the webcam source's file
// player reads (y4m_reader.hpp), written by `earshot track simulate-video`
// and the tests. The header is
//   YUV4MPEG2 W<width> H<height> F<num>:<den> Ip A1:1 Cmono\n
// and each frame is "FRAME\n" followed by width * height bytes, row by row.
#pragma once

#include <cstdint>
#include <fstream>
#include <iosfwd>
#include <memory>
#include <span>
#include <string>

namespace earshot::webcam {

class Y4mWriter {
 public:
  /// Opens (truncates) `path` and writes the header. The frame rate is
  /// num / den frames per second. Throws std::runtime_error naming the file
  /// when it cannot be written, std::invalid_argument for bad sizes or rates.
  Y4mWriter(const std::string& path, int width, int height, int fps_num, int fps_den = 1);
  /// Writes to `out` (kept by reference; "stream" in messages) instead of a file.
  Y4mWriter(std::ostream& out, int width, int height, int fps_num, int fps_den = 1);

  /// Appends one frame of exactly width * height bytes (else
  /// std::invalid_argument); std::runtime_error when the write fails.
  void write(std::span<const std::uint8_t> pixels);
  /// Flushes and closes (a file; a stream is flushed); std::runtime_error
  /// when the data did not reach it.
  void close();

  [[nodiscard]] long frames() const { return frames_; }

 private:
  void write_header(int fps_num, int fps_den);

  std::string name_;
  std::unique_ptr<std::ofstream> file_;
  std::ostream* out_ = nullptr;
  int width_, height_;
  long frames_ = 0;
};

}  // namespace earshot::webcam
