// Fuzzes the Scene JSON parser: a scene or InputError, nothing else.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "earshot/errors.hpp"
#include "earshot/scenes/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto s = earshot::scenes::parse_scene(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json");
    if (!(s.duration_s >= 0.0) || !(s.sample_rate >= 8000.0)) std::abort();
  } catch (const earshot::InputError&) {
  }
  return 0;
}
