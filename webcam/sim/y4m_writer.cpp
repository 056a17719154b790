#include "earshot/webcam/y4m_writer.hpp"

#include <stdexcept>

namespace earshot::webcam {

Y4mWriter::Y4mWriter(const std::string& path, int width, int height, int fps_num, int fps_den)
    : path_(path), width_(width), height_(height) {
  if (width <= 0 || height <= 0)
    throw std::invalid_argument(path + ": frame size " + std::to_string(width) + "x" + std::to_string(height));
  if (fps_num <= 0 || fps_den <= 0)
    throw std::invalid_argument(path + ": frame rate " + std::to_string(fps_num) + ":" + std::to_string(fps_den));
  out_.open(path, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error(path + ": cannot open for writing");
  out_ << "YUV4MPEG2 W" << width << " H" << height << " F" << fps_num << ':' << fps_den << " Ip A1:1 Cmono\n";
  if (!out_) throw std::runtime_error(path + ": write failed");
}

void Y4mWriter::write(std::span<const std::uint8_t> pixels) {
  const auto need = static_cast<size_t>(width_) * static_cast<size_t>(height_);
  if (pixels.size() != need)
    throw std::invalid_argument(path_ + ": frame of " + std::to_string(pixels.size()) + " bytes, expected " +
                                std::to_string(need));
  out_ << "FRAME\n";
  out_.write(reinterpret_cast<const char*>(pixels.data()), static_cast<std::streamsize>(pixels.size()));
  if (!out_) throw std::runtime_error(path_ + ": write failed at frame " + std::to_string(frames_));
  ++frames_;
}

void Y4mWriter::close() {
  if (!out_.is_open()) return;
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok || out_.fail()) throw std::runtime_error(path_ + ": write failed");
}

}  // namespace earshot::webcam
