// Fuzzes the Pose track CSV reader (common/pose_track_csv.hpp) through the
// scenes::PoseTrack built on it: a track or InputError; interpolated poses
// are finite with unit quaternions.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/scenes/pose_track.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const auto tr = earshot::scenes::PoseTrack::read(in, "fuzz.csv");
    for (double t : {-1.0, 0.0, 0.5, 1e3}) {
      const auto s = tr.at(t);
      double n = 0;
      for (double q : s.orientation) n += q * q;
      if (!std::isfinite(n) || std::abs(n - 1.0) > 1e-6) std::abort();
      for (double p : s.position)
        if (!std::isfinite(p)) std::abort();
    }
  } catch (const earshot::InputError&) {
  }
  return 0;
}
