// The LED detector: a threshold from the frame's own statistics, 8-connected
// components, a compactness test and intensity-weighted sub-pixel centroids
// of the four brightest compact blobs.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "earshot/webcam/dot_detector.hpp"
#include "view_check.hpp"

namespace earshot::webcam {
namespace {

// The threshold sits this many robust standard deviations (1.4826 MAD) of
// the background above its median, and at least kMinMargin grey levels:
// six sigma of Gaussian noise is crossed by ~1 pixel in 10^9, and the floor
// keeps a flat (MAD 0) frame's quantisation steps out.
constexpr double kSigmas = 6.0;
constexpr int kMinMargin = 16;
// Background statistics from about this many pixels (a regular subsample).
constexpr long kSamples = 16384;
// Compactness: an LED is a round spot, a motion-blurred one a short streak.
// The bounding box must be at least this full (a disc fills pi/4, a
// 3-pixel-wide diagonal streak of length 8 about 0.37) and no longer than
// kMaxAspect times its width; blobs of up to kSmallArea pixels skip the fill
// test (two diagonal pixels fill half their box).
constexpr double kMinFill = 0.3;
constexpr double kMaxAspect = 5.0;
constexpr int kSmallArea = 4;
// Candidates recorded per frame; more are labelled but not measured (a
// frame with this many compact bright spots is not showing a beacon).
constexpr size_t kMaxBlobs = 1024;
// The centroid window reaches this far beyond the blob's box; its border
// gives the local background.
constexpr int kWindowMargin = 2;

struct Blob {
  std::int32_t label = 0;
  int area = 0;
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // bounding box, inclusive
  double flux = 0.0, cx = 0.0, cy = 0.0;
};

class LedDetector final : public DotDetector {
 public:
  explicit LedDetector(const LedOptions& options) : opt_(options) { blobs_.reserve(kMaxBlobs); }

  Detection detect(const GrayView& frame) override {
    Detection out;
    if (!detail::check_view(frame)) return out;
    prepare(frame.width, frame.height);
    const int thr = threshold(frame);
    label_components(frame, thr);
    for (Blob& b : blobs_) measure(frame, b);
    // The four brightest compact blobs, brightest first.
    std::array<const Blob*, 4> best{};
    int n = 0;
    for (const Blob& b : blobs_) {
      if (b.flux <= 0.0) continue;
      int at = n < 4 ? n++ : 4;
      if (at == 4 && b.flux <= best[3]->flux) continue;
      if (at == 4) at = 3;
      while (at > 0 && best[static_cast<size_t>(at - 1)]->flux < b.flux) {
        best[static_cast<size_t>(at)] = best[static_cast<size_t>(at - 1)];
        --at;
      }
      best[static_cast<size_t>(at)] = &b;
    }
    out.count = n;
    for (int i = 0; i < n; ++i) {
      const Blob& b = *best[static_cast<size_t>(i)];
      out.points[static_cast<size_t>(i)] = {b.cx, b.cy, static_cast<double>(b.area)};
    }
    clear_labels();
    return out;
  }

  [[nodiscard]] std::string describe() const override { return "leds"; }

 private:
  void prepare(int w, int h) {
    if (w == w_ && h == h_) return;
    w_ = w;
    h_ = h;
    const auto n = static_cast<size_t>(w) * static_cast<size_t>(h);
    label_.assign(n, 0);
    pixels_.assign(n, 0);
  }

  /// Median + max(6 sigma, 16) of a regular subsample, sigma from the MAD.
  int threshold(const GrayView& f) {
    hist_.fill(0);
    const long total = static_cast<long>(f.width) * f.height;
    const int step = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(total) / kSamples)));
    long count = 0;
    for (int y = step / 2; y < f.height; y += step) {
      const std::uint8_t* row = f.pixels.data() + static_cast<std::ptrdiff_t>(y) * f.stride;
      for (int x = step / 2; x < f.width; x += step) {
        ++hist_[row[x]];
        ++count;
      }
    }
    const int median = median_of(hist_, count);
    // |v - median| histogram, read straight from the value histogram.
    std::array<long, 256> dev{};
    for (int v = 0; v < 256; ++v) dev[static_cast<size_t>(std::abs(v - median))] += hist_[static_cast<size_t>(v)];
    const double sigma = 1.4826 * median_of(dev, count);
    const int margin = std::max(kMinMargin, static_cast<int>(std::ceil(kSigmas * sigma)));
    return std::min(255, median + margin);
  }

  static int median_of(const std::array<long, 256>& h, long count) {
    long seen = 0;
    for (int v = 0; v < 256; ++v) {
      seen += h[static_cast<size_t>(v)];
      if (2 * seen >= count) return v;
    }
    return 255;
  }

  /// 8-connected components of the pixels >= thr; records each component's
  /// area and box, and the compact ones of an LED's size as candidates.
  void label_components(const GrayView& f, int thr) {
    blobs_.clear();
    used_ = 0;
    std::int32_t next = 0;
    const auto t = static_cast<std::uint8_t>(thr);
    for (int y = 0; y < f.height; ++y) {
      const std::uint8_t* row = f.pixels.data() + static_cast<std::ptrdiff_t>(y) * f.stride;
      for (int x = 0; x < f.width; ++x) {
        if (row[x] < t || label_[index(x, y)] != 0) continue;
        Blob b;
        b.label = ++next;
        b.x0 = b.x1 = x;
        b.y0 = b.y1 = y;
        // Breadth-first fill; pixels_ holds every visited pixel of the frame.
        size_t head = used_;
        pixels_[used_++] = static_cast<std::int32_t>(index(x, y));
        label_[index(x, y)] = b.label;
        while (head < used_) {
          const std::int32_t p = pixels_[head++];
          const int px = p % w_, py = p / w_;
          ++b.area;
          b.x0 = std::min(b.x0, px);
          b.x1 = std::max(b.x1, px);
          b.y0 = std::min(b.y0, py);
          b.y1 = std::max(b.y1, py);
          for (int dy = -1; dy <= 1; ++dy) {
            const int ny = py + dy;
            if (ny < 0 || ny >= f.height) continue;
            const std::uint8_t* nrow = f.pixels.data() + static_cast<std::ptrdiff_t>(ny) * f.stride;
            for (int dx = -1; dx <= 1; ++dx) {
              const int nx = px + dx;
              if (nx < 0 || nx >= f.width || nrow[nx] < t) continue;
              std::int32_t& l = label_[index(nx, ny)];
              if (l != 0) continue;
              l = b.label;
              pixels_[used_++] = static_cast<std::int32_t>(index(nx, ny));
            }
          }
        }
        if (compact(b) && blobs_.size() < kMaxBlobs) blobs_.push_back(b);
      }
    }
  }

  [[nodiscard]] bool compact(const Blob& b) const {
    if (b.area < opt_.min_area_px || b.area > opt_.max_area_px) return false;
    const int bw = b.x1 - b.x0 + 1, bh = b.y1 - b.y0 + 1;
    if (std::max(bw, bh) > kMaxAspect * std::min(bw, bh)) return false;
    return b.area <= kSmallArea || b.area >= kMinFill * bw * bh;
  }

  /// Sub-pixel centroid and integrated intensity: weights (I - background)
  /// over the blob and the ring of pixels around it (the spot's skirt below
  /// the threshold), the background being the median of the window's border.
  void measure(const GrayView& f, Blob& b) const {
    const int x0 = std::max(0, b.x0 - kWindowMargin), x1 = std::min(f.width - 1, b.x1 + kWindowMargin);
    const int y0 = std::max(0, b.y0 - kWindowMargin), y1 = std::min(f.height - 1, b.y1 + kWindowMargin);
    std::array<long, 256> ring{};
    long ring_n = 0;
    for (int y = y0; y <= y1; ++y) {
      const std::uint8_t* row = f.pixels.data() + static_cast<std::ptrdiff_t>(y) * f.stride;
      const bool edge_row = y == y0 || y == y1;
      for (int x = x0; x <= x1; x += (edge_row || x == x1) ? 1 : x1 - x0) {
        ++ring[row[x]];
        ++ring_n;
      }
    }
    const double bg = median_of(ring, ring_n);
    double sw = 0.0, sx = 0.0, sy = 0.0;
    for (int y = y0; y <= y1; ++y) {
      const std::uint8_t* row = f.pixels.data() + static_cast<std::ptrdiff_t>(y) * f.stride;
      for (int x = x0; x <= x1; ++x) {
        const std::int32_t l = label_[index(x, y)];
        if (l != b.label && (l != 0 || !touches(x, y, b.label))) continue;
        const double w = static_cast<double>(row[x]) - bg;
        if (w <= 0.0) continue;
        sw += w;
        sx += w * x;
        sy += w * y;
      }
    }
    b.flux = sw;
    if (sw > 0.0) {
      b.cx = sx / sw;
      b.cy = sy / sw;
    }
  }

  /// Whether an 8-neighbour of (x, y) belongs to component `label`.
  [[nodiscard]] bool touches(int x, int y, std::int32_t label) const {
    for (int dy = -1; dy <= 1; ++dy) {
      const int ny = y + dy;
      if (ny < 0 || ny >= h_) continue;
      for (int dx = -1; dx <= 1; ++dx) {
        const int nx = x + dx;
        if (nx >= 0 && nx < w_ && label_[index(nx, ny)] == label) return true;
      }
    }
    return false;
  }

  void clear_labels() {
    for (size_t i = 0; i < used_; ++i) label_[static_cast<size_t>(pixels_[i])] = 0;
    used_ = 0;
  }

  [[nodiscard]] size_t index(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(w_) + static_cast<size_t>(x);
  }

  LedOptions opt_;
  int w_ = 0, h_ = 0;
  std::vector<std::int32_t> label_;   // component per pixel, 0 none (cleared after each frame)
  std::vector<std::int32_t> pixels_;  // the pixels visited this frame, component by component
  size_t used_ = 0;
  std::vector<Blob> blobs_;
  std::array<long, 256> hist_{};
};

}  // namespace

std::unique_ptr<DotDetector> make_led_detector(const LedOptions& options) {
  if (!(options.min_area_px >= 0.0) || !(options.max_area_px >= options.min_area_px))
    throw std::invalid_argument("LED detector: blob areas need 0 <= min_area_px (" +
                                std::to_string(options.min_area_px) + ") <= max_area_px (" +
                                std::to_string(options.max_area_px) + ")");
  return std::make_unique<LedDetector>(options);
}

}  // namespace earshot::webcam
