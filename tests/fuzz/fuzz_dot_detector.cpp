// Fuzzes both webcam detectors on frames made of the input bytes: camera
// pixels are outside bytes too. The first two bytes give the width and the
// height (1..96), the third the stride's padding; the rest is the picture
// (zero-filled when short). Every detection must hold at most four finite
// points, LED centroids inside the frame's pixels, tag corners within two
// pixels of them, and neither detector may crash or throw.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

#include "earshot/webcam/dot_detector.hpp"

namespace {

void check(const earshot::webcam::Detection& d, int w, int h, bool tag) {
  if (d.count < 0 || d.count > 4) std::abort();
  for (int i = 0; i < d.count; ++i) {
    const auto& p = d.points[static_cast<std::size_t>(i)];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.size) || p.size < 0.0) std::abort();
    const double margin = tag ? 2.0 : 0.5;
    if (p.x < -margin || p.y < -margin || p.x > w - 1 + margin || p.y > h - 1 + margin) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 3) return 0;
  const int w = 1 + data[0] % 96, h = 1 + data[1] % 96, pad = data[2] % 8;
  const std::ptrdiff_t stride = w + pad;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(stride) * static_cast<std::size_t>(h), 0);
  std::copy_n(data + 3, std::min(size - 3, pixels.size()), pixels.begin());
  const earshot::webcam::GrayView view{pixels, w, h, stride};

  static const auto leds = earshot::webcam::make_led_detector();
  static const auto tags = [] {
    earshot::webcam::AprilTagOptions o;
    o.family = "tag16h5";  // the smallest family: the most likely to be "found" in noise
    return earshot::webcam::make_apriltag_detector(o);
  }();
  check(leds->detect(view), w, h, false);
  check(tags->detect(view), w, h, true);
  return 0;
}
