#include "earshot/webcam/y4m_writer.hpp"

#include <ostream>
#include <stdexcept>

namespace earshot::webcam {

Y4mWriter::Y4mWriter(const std::string& path, int width, int height, int fps_num, int fps_den)
    : name_(path), width_(width), height_(height) {
  write_header(fps_num, fps_den);
}

Y4mWriter::Y4mWriter(std::ostream& out, int width, int height, int fps_num, int fps_den)
    : name_("stream"), out_(&out), width_(width), height_(height) {
  write_header(fps_num, fps_den);
}

void Y4mWriter::write_header(int fps_num, int fps_den) {
  if (width_ <= 0 || height_ <= 0)
    throw std::invalid_argument(name_ + ": frame size " + std::to_string(width_) + "x" + std::to_string(height_));
  if (fps_num <= 0 || fps_den <= 0)
    throw std::invalid_argument(name_ + ": frame rate " + std::to_string(fps_num) + ":" + std::to_string(fps_den));
  if (!out_) {
    file_ = std::make_unique<std::ofstream>(name_, std::ios::binary | std::ios::trunc);
    if (!*file_) throw std::runtime_error(name_ + ": cannot open for writing");
    out_ = file_.get();
  }
  *out_ << "YUV4MPEG2 W" << width_ << " H" << height_ << " F" << fps_num << ':' << fps_den << " Ip A1:1 Cmono\n";
  if (!*out_) throw std::runtime_error(name_ + ": write failed");
}

void Y4mWriter::write(std::span<const std::uint8_t> pixels) {
  const auto need = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  if (pixels.size() != need)
    throw std::invalid_argument(name_ + ": frame of " + std::to_string(pixels.size()) + " bytes, expected " +
                                std::to_string(need));
  *out_ << "FRAME\n";
  out_->write(reinterpret_cast<const char*>(pixels.data()), static_cast<std::streamsize>(pixels.size()));
  if (!*out_) throw std::runtime_error(name_ + ": write failed at frame " + std::to_string(frames_));
  ++frames_;
}

void Y4mWriter::close() {
  if (file_ && !file_->is_open()) return;  // closed already
  out_->flush();
  bool ok = static_cast<bool>(*out_);
  if (file_ && file_->is_open()) {
    file_->close();
    ok = ok && !file_->fail();
  }
  if (!ok) throw std::runtime_error(name_ + ": write failed");
}

}  // namespace earshot::webcam
