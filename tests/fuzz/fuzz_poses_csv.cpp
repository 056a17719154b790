// Fuzzes the Poses CSV reader: frames or InputError; every pose read is finite.
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/tracker/core/poses_csv.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  earshot::tracker::PosesCsvReader reader(in, "fuzz.csv");
  try {
    while (auto r = reader.next())
      if (!r->pose.finite()) std::abort();
  } catch (const earshot::InputError&) {
  }
  return 0;
}
