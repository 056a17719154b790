// YUV4MPEG2 (.y4m) files: raw video that stands in for a webcam in tests and
// recordings (ffmpeg writes it: `ffmpeg -i in.mp4 -pix_fmt gray out.y4m`).
//
// The header line "YUV4MPEG2 W640 H480 F30:1 Ip A1:1 C420jpeg XCOMMENT" is
// followed by frames, each "FRAME[ params]\n" and the planes. Only the luma
// (Y) plane is kept: the detectors see grey. Colour spaces read: mono,
// 420jpeg, 420paldv, 420mpeg2, 420, 422 and 444 (8 bits per sample); others
// are refused by name. Errors name the origin, the frame and the field.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <istream>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace earshot::webcam {

struct Y4mHeader {
  int width = 0;
  int height = 0;
  int fps_num = 0;  ///< frame rate fps_num / fps_den (F)
  int fps_den = 1;
  char interlace = 'p';         ///< I: p, t, b, m or '?' (not given)
  std::string aspect = "0:0";   ///< A, as written
  std::string colour = "420jpeg";  ///< C, as written (420jpeg when not given)
  std::size_t chroma_bytes = 0;    ///< bytes after the luma plane in each frame

  [[nodiscard]] double fps() const { return static_cast<double>(fps_num) / fps_den; }
  /// Largest width * height accepted: 8192 x 4320 (8K), so a corrupt header
  /// cannot make the reader allocate gigabytes.
  static constexpr long long kMaxPixels = 8192LL * 4320LL;
  static constexpr int kMaxSide = 16384;
};

/// Parses a header line (without its '\n'). Throws earshot::InputError
/// naming `origin` and the field.
[[nodiscard]] Y4mHeader parse_y4m_header(std::string_view line, std::string_view origin);

class Y4mReader {
 public:
  /// Opens a file and reads its header (InputError when unreadable or bad).
  explicit Y4mReader(const std::filesystem::path& path);
  /// Reads from a stream the caller keeps alive; `origin` names it in errors.
  Y4mReader(std::istream& in, std::string origin);

  [[nodiscard]] const Y4mHeader& header() const { return header_; }
  [[nodiscard]] const std::string& origin() const { return origin_; }

  /// The next frame's luma plane (width * height bytes, row after row),
  /// valid until the next call; an empty span at the end of the stream.
  /// Throws InputError naming the frame (1-based) for a bad FRAME line or a
  /// truncated frame.
  std::span<const std::uint8_t> next();
  /// Frames read so far.
  [[nodiscard]] long frames() const { return frames_; }

 private:
  void read_header();

  std::unique_ptr<std::ifstream> file_;
  std::istream* in_ = nullptr;
  std::string origin_;
  Y4mHeader header_;
  std::vector<std::uint8_t> luma_;
  long frames_ = 0;
};

}  // namespace earshot::webcam
