// Fuzzes the Y4M reader: frames of exactly width * height bytes or
// InputError; never more frames than the bytes can hold.
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/webcam/y4m_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    earshot::webcam::Y4mReader r(in, "fuzz.y4m");
    const auto& h = r.header();
    if (h.width < 1 || h.height < 1 || !(h.fps() > 0.0)) std::abort();
    const std::size_t luma = static_cast<std::size_t>(h.width) * static_cast<std::size_t>(h.height);
    std::size_t bytes = 0;
    for (auto f = r.next(); !f.empty(); f = r.next()) {
      if (f.size() != luma) std::abort();
      bytes += luma + h.chroma_bytes;
      if (bytes > size) std::abort();
    }
  } catch (const earshot::InputError&) {
  }
  return 0;
}
