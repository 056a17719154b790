// Fuzzes the Dots CSV reader: any bytes must give frames or an InputError,
// never a crash, a hang or another exception; parsed dots are finite.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/tracker/core/dots_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  earshot::tracker::DotsCsvReader reader(in, "fuzz.csv");
  try {
    while (auto f = reader.next()) {
      if (!std::isfinite(f->t)) std::abort();
      for (const auto& s : f->slots)
        if (s && !s->allFinite()) std::abort();
    }
  } catch (const earshot::InputError&) {
  }
  for (bool truth : {false, true}) {
    try {
      (void)earshot::tracker::parse_dots_line(text, truth, "fuzz.csv", 1);
    } catch (const earshot::InputError&) {
    }
  }
  return 0;
}
