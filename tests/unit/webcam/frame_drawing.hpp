// Frames drawn by hand for the detector tests: a float canvas, pixel-
// integrated Gaussian spots (pixel centres at integers), discs, 8-bit output.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "earshot/webcam/dot_detector.hpp"

namespace earshot::webcam::testing {

struct Canvas {
  int width = 0, height = 0;
  std::vector<double> v;
  std::vector<std::uint8_t> bytes;

  Canvas(int w, int h, double background) : width(w), height(h), v(static_cast<size_t>(w) * h, background) {}

  double& at(int x, int y) { return v[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)]; }

  /// A Gaussian spot of standard deviation `sigma` whose peak (before pixel
  /// integration) is `peak` grey levels, centred at (u, v).
  void spot(double u, double vv, double sigma, double peak) {
    const double flux = peak * 2.0 * std::numbers::pi * sigma * sigma;
    auto cdf = [](double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); };
    const int r = static_cast<int>(std::ceil(6.0 * sigma)) + 1;
    for (int y = std::max(0, static_cast<int>(vv) - r); y <= std::min(height - 1, static_cast<int>(vv) + r); ++y)
      for (int x = std::max(0, static_cast<int>(u) - r); x <= std::min(width - 1, static_cast<int>(u) + r); ++x)
        at(x, y) += flux * (cdf((x + 0.5 - u) / sigma) - cdf((x - 0.5 - u) / sigma)) *
                    (cdf((y + 0.5 - vv) / sigma) - cdf((y - 0.5 - vv) / sigma));
  }

  /// A uniform disc (anti-aliased over one pixel) adding `level`.
  void disc(double u, double vv, double radius, double level) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const double d = std::hypot(x - u, y - vv) - radius;
        at(x, y) += level * std::clamp(0.5 - d, 0.0, 1.0);
      }
  }

  /// Scales every pixel (an exposure change).
  void scale(double g) {
    for (double& p : v) p *= g;
  }

  /// 8-bit frame, clipped (saturation) and rounded.
  GrayView view() {
    bytes.resize(v.size());
    for (size_t i = 0; i < v.size(); ++i) bytes[i] = static_cast<std::uint8_t>(std::clamp(std::lround(v[i]), 0L, 255L));
    return {bytes, width, height, width};
  }
};

/// Root-mean-square distance from each truth point to the nearest found point.
inline double rms_to_nearest(const Detection& d, const std::vector<std::array<double, 2>>& truth) {
  double sum = 0.0;
  for (const auto& t : truth) {
    double best = 1e300;
    for (int i = 0; i < d.count; ++i) {
      const Point& p = d.points[static_cast<size_t>(i)];
      best = std::min(best, std::hypot(p.x - t[0], p.y - t[1]));
    }
    sum += best * best;
  }
  return std::sqrt(sum / static_cast<double>(truth.size()));
}

}  // namespace earshot::webcam::testing
