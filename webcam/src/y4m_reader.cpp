#include "earshot/webcam/y4m_reader.hpp"

#include <algorithm>
#include <charconv>
#include <limits>

#include "earshot/errors.hpp"

namespace earshot::webcam {
namespace {

constexpr std::string_view kMagic = "YUV4MPEG2";
constexpr std::size_t kMaxLine = 4096;  // header and FRAME lines; longer is not Y4M

bool parse_int(std::string_view text, int& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return !text.empty() && ec == std::errc{} && end == text.data() + text.size();
}

/// Reads one line up to '\n' (not kept). False at a clean end of stream
/// (nothing read); throws when the line is too long or the stream ends inside it.
bool read_line(std::istream& in, std::string& line, std::string_view origin, long frame) {
  line.clear();
  for (;;) {
    const int c = in.get();
    if (c == std::char_traits<char>::eof()) {
      if (line.empty()) return false;
      throw InputError::at(origin, 0, frame ? "FRAME" : "header",
                           (frame ? "frame " + std::to_string(frame) + ": " : std::string()) +
                               "the stream ends inside a line");
    }
    if (c == '\n') return true;
    if (line.size() >= kMaxLine)
      throw InputError::at(origin, 0, frame ? "FRAME" : "header",
                           (frame ? "frame " + std::to_string(frame) + ": " : std::string()) + "line longer than " +
                               std::to_string(kMaxLine) + " bytes");
    line.push_back(static_cast<char>(c));
  }
}

}  // namespace

Y4mHeader parse_y4m_header(std::string_view line, std::string_view origin) {
  const auto fail = [&](std::string_view field, const std::string& why) {
    return InputError::at(origin, 0, field, why);
  };
  if (!line.starts_with(kMagic) || (line.size() > kMagic.size() && line[kMagic.size()] != ' '))
    throw fail("header", "not a YUV4MPEG2 stream (the file must start with 'YUV4MPEG2 ')");
  Y4mHeader h;
  bool have_w = false, have_h = false, have_f = false;
  std::string_view rest = line.substr(kMagic.size());
  while (!rest.empty()) {
    if (rest.front() == ' ') {
      rest.remove_prefix(1);
      continue;
    }
    const std::size_t end = rest.find(' ');
    const std::string_view token = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end);
    const char tag = token.front();
    const std::string_view value = token.substr(1);
    const std::string field(1, tag);
    switch (tag) {
      case 'W':
      case 'H': {
        int v = 0;
        if (!parse_int(value, v) || v < 1 || v > Y4mHeader::kMaxSide)
          throw fail(field, "bad " + std::string(tag == 'W' ? "width" : "height") + " '" + std::string(value) + "' (1-" +
                                std::to_string(Y4mHeader::kMaxSide) + ")");
        (tag == 'W' ? h.width : h.height) = v;
        (tag == 'W' ? have_w : have_h) = true;
        break;
      }
      case 'F': {
        const std::size_t colon = value.find(':');
        if (colon == std::string_view::npos || !parse_int(value.substr(0, colon), h.fps_num) ||
            !parse_int(value.substr(colon + 1), h.fps_den) || h.fps_num < 1 || h.fps_den < 1 ||
            static_cast<double>(h.fps_num) / h.fps_den > 10000.0 || static_cast<double>(h.fps_num) / h.fps_den < 0.01)
          throw fail(field, "bad frame rate '" + std::string(value) + "' (NUM:DEN, e.g. 30:1 or 30000:1001)");
        have_f = true;
        break;
      }
      case 'I':
        if (value.size() != 1 || std::string_view("ptbm?").find(value.front()) == std::string_view::npos)
          throw fail(field, "bad interlacing '" + std::string(value) + "' (p, t, b or m)");
        h.interlace = value.front();
        break;
      case 'A': h.aspect = std::string(value); break;
      case 'C': h.colour = std::string(value); break;
      case 'X': break;  // comments and extensions: nothing we need
      default: throw fail(field, "unknown header parameter '" + std::string(token) + "'");
    }
  }
  if (!have_w) throw fail("W", "the header gives no width");
  if (!have_h) throw fail("H", "the header gives no height");
  if (!have_f) throw fail("F", "the header gives no frame rate");
  if (static_cast<long long>(h.width) * h.height > Y4mHeader::kMaxPixels)
    throw fail("W", std::to_string(h.width) + "x" + std::to_string(h.height) + " is larger than 8192x4320");
  const std::size_t w = static_cast<std::size_t>(h.width), ht = static_cast<std::size_t>(h.height);
  const std::size_t cw = (w + 1) / 2, ch = (ht + 1) / 2;
  const std::string& c = h.colour;
  if (c == "mono") h.chroma_bytes = 0;
  else if (c == "420jpeg" || c == "420paldv" || c == "420mpeg2" || c == "420") h.chroma_bytes = 2 * cw * ch;
  else if (c == "422") h.chroma_bytes = 2 * cw * ht;
  else if (c == "444") h.chroma_bytes = 2 * w * ht;
  else
    throw fail("C", "unsupported colour space '" + c +
                        "' (8-bit mono, 420jpeg, 420paldv, 420mpeg2, 420, 422 or 444; convert with ffmpeg -pix_fmt gray)");
  return h;
}

Y4mReader::Y4mReader(const std::filesystem::path& path)
    : file_(std::make_unique<std::ifstream>(path, std::ios::binary)), in_(file_.get()), origin_(path.string()) {
  if (!*file_) throw InputError::at(origin_, 0, "", "cannot open the video file");
  read_header();
}

Y4mReader::Y4mReader(std::istream& in, std::string origin) : in_(&in), origin_(std::move(origin)) { read_header(); }

void Y4mReader::read_header() {
  std::string line;
  if (!read_line(*in_, line, origin_, 0)) throw InputError::at(origin_, 0, "header", "empty file (no YUV4MPEG2 header)");
  header_ = parse_y4m_header(line, origin_);
}

std::span<const std::uint8_t> Y4mReader::next() {
  const long frame = frames_ + 1;
  std::string line;
  if (!read_line(*in_, line, origin_, frame)) return {};
  const auto fail = [&](std::string_view field, const std::string& why) {
    return InputError::at(origin_, 0, field, "frame " + std::to_string(frame) + ": " + why);
  };
  if (!line.starts_with("FRAME") || (line.size() > 5 && line[5] != ' '))
    throw fail("FRAME", "expected a 'FRAME' line, got '" + line.substr(0, 16) + "'");
  // Frame parameters (I, A, X) change nothing we read.
  const std::size_t luma = static_cast<std::size_t>(header_.width) * static_cast<std::size_t>(header_.height);
  // Read in chunks, growing the buffer only as bytes arrive: a header that
  // promises a huge frame over a short file costs no huge allocation.
  std::size_t got = 0;
  while (got < luma) {
    const std::size_t chunk = std::min<std::size_t>(luma - got, std::size_t{1} << 20);
    if (luma_.size() < got + chunk) luma_.resize(got + chunk);
    in_->read(reinterpret_cast<char*>(luma_.data() + got), static_cast<std::streamsize>(chunk));
    got += static_cast<std::size_t>(in_->gcount());
    if (static_cast<std::size_t>(in_->gcount()) != chunk) break;
  }
  if (got != luma) throw fail("Y", "truncated: " + std::to_string(got) + " of " + std::to_string(luma) + " luma bytes");
  luma_.resize(luma);
  if (header_.chroma_bytes > 0) {
    in_->ignore(static_cast<std::streamsize>(header_.chroma_bytes));
    if (static_cast<std::size_t>(in_->gcount()) != header_.chroma_bytes)
      throw fail("C", "truncated: " + std::to_string(in_->gcount()) + " of " + std::to_string(header_.chroma_bytes) +
                          " chroma bytes");
  }
  frames_ = frame;
  return luma_;
}

}  // namespace earshot::webcam
