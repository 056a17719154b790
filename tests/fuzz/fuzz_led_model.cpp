// Fuzzes the Model JSON parser: a model or InputError; accepted models are finite.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "earshot/errors.hpp"
#include "earshot/tracker/core/led_model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto m = earshot::tracker::parse_led_model(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json");
    for (const auto& p : m.leds_mm)
      if (!p.allFinite()) std::abort();
  } catch (const earshot::InputError&) {
  }
  return 0;
}
