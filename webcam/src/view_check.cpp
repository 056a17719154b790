#include "view_check.hpp"

#include <stdexcept>
#include <string>

namespace earshot::webcam::detail {

bool check_view(const GrayView& frame) {
  auto bad = [&](const std::string& why) {
    throw std::invalid_argument("webcam frame " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                                " stride " + std::to_string(frame.stride) + ": " + why);
  };
  if (frame.width < 0 || frame.height < 0) bad("negative size");
  if (frame.stride < frame.width) bad("stride shorter than a row");
  if (frame.width == 0 || frame.height == 0) return false;
  // stride * (height - 1) + width, in 64 bits: no overflow for any int sizes.
  const auto need = static_cast<unsigned long long>(frame.stride) * static_cast<unsigned long long>(frame.height - 1) +
                    static_cast<unsigned long long>(frame.width);
  if (frame.pixels.size() < need)
    bad("needs " + std::to_string(need) + " bytes, the span has " + std::to_string(frame.pixels.size()));
  return true;
}

}  // namespace earshot::webcam::detail
