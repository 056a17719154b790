// Fuzzes the calibration YAML parser: a calibration with finite, positive
// focal lengths or InputError; undistortion of a few points stays finite.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "earshot/errors.hpp"
#include "earshot/webcam/camera_calibration.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace earshot::webcam;
  using earshot::tracker::Vec2;
  try {
    const CameraCalibration c =
        parse_camera_calibration(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.yml");
    if (!(c.fx > 0.0) || !(c.fy > 0.0) || !std::isfinite(c.fx) || !std::isfinite(c.fy)) std::abort();
    for (const double d : c.distortion)
      if (!std::isfinite(d)) std::abort();
    for (const Vec2& p : {Vec2(0, 0), Vec2(c.cx, c.cy), Vec2(1e4, -1e4)}) {
      if (!c.undistort_fixed_point(p, 20).allFinite()) std::abort();
      const auto u = c.undistort(p);
      if (u && (!u->allFinite() || !((c.distort(*u) - p).norm() <= earshot::webcam::kUndistortTolerancePx))) std::abort();
    }
    if (c.image_width > 0) (void)c.scaled_to(640, 480, "fuzz.yml");
  } catch (const earshot::InputError&) {
  }
  return 0;
}
