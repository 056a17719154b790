#include "earshot/webcam/video_sim.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace earshot::webcam {
namespace {

using tracker::Pose;
using tracker::Vec2;
using tracker::Vec3;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kTagHalfAngleDeg = 75.0;  // a tag turned further is a sliver
constexpr double kLampRadiance = 3000.0;

[[noreturn]] void bad(const std::string& what) { throw std::invalid_argument("synthetic video: " + what); }

/// Standard normal CDF.
double phi(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }

/// Smooth value noise in [-1, 1] on a grid of `cell` pixels.
class ValueNoise {
 public:
  ValueNoise(int w, int h, double cell, std::mt19937_64& rng)
      : cell_(cell), gw_(static_cast<int>(w / cell) + 2), gh_(static_cast<int>(h / cell) + 2) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    grid_.resize(static_cast<size_t>(gw_) * static_cast<size_t>(gh_));
    for (double& g : grid_) g = u(rng);
  }
  [[nodiscard]] double at(double x, double y) const {
    const double gx = x / cell_, gy = y / cell_;
    const int ix = std::min(gw_ - 2, static_cast<int>(gx)), iy = std::min(gh_ - 2, static_cast<int>(gy));
    auto smooth = [](double f) { return f * f * (3.0 - 2.0 * f); };
    const double fx = smooth(gx - ix), fy = smooth(gy - iy);
    auto g = [&](int a, int b) { return grid_[static_cast<size_t>(b) * static_cast<size_t>(gw_) + static_cast<size_t>(a)]; };
    const double top = g(ix, iy) + (g(ix + 1, iy) - g(ix, iy)) * fx;
    const double bot = g(ix, iy + 1) + (g(ix + 1, iy + 1) - g(ix, iy + 1)) * fx;
    return top + (bot - top) * fy;
  }

 private:
  double cell_;
  int gw_, gh_;
  std::vector<double> grid_;
};

}  // namespace

tracker::Camera video_camera(const VideoSimConfig& cfg) {
  const double f = 0.5 * cfg.width / std::tan(0.5 * cfg.hfov_deg * kDeg);
  // Centred under the pixel convention the renderer draws with (pixel
  // centres at whole numbers), as a webcam source without a calibration assumes.
  tracker::Camera c = tracker::Camera::with_focal(f, cfg.width, cfg.height);
  c.cx = (cfg.width - 1) / 2.0;
  c.cy = (cfg.height - 1) / 2.0;
  return c;
}

tracker::LedModel video_model(const VideoSimConfig& cfg) {
  if (cfg.beacon == BeaconKind::leds) return cfg.leds;
  tracker::LedModel m;
  const auto c = tag_corners_mm(cfg.tag_size_mm);
  for (size_t k = 0; k < 4; ++k) m.leds_mm[k] = Vec3(c[k][0], c[k][1], c[k][2]);
  m.axis = Vec3(0.0, 0.0, -1.0);
  m.half_angle = kTagHalfAngleDeg * kDeg;
  return m;
}

tracker::DotFrame VideoFrame::dot_frame() const {
  tracker::DotFrame f;
  f.t = t;
  tracker::GroundTruth gt;
  gt.pose = truth;
  for (size_t k = 0; k < 4; ++k) {
    f.slots[k] = points[k];
    gt.slot_led[k] = points[k] ? static_cast<int>(k) + 1 : 0;
  }
  f.truth = gt;
  return f;
}

namespace {

VideoSimConfig checked(VideoSimConfig c) {
  if (c.width < 8 || c.height < 8 || c.width > 8192 || c.height > 8192)
    bad("frame size " + std::to_string(c.width) + "x" + std::to_string(c.height) + " (8..8192 per side)");
  if (!(c.fps > 0.0 && c.fps <= 1000.0)) bad("fps " + std::to_string(c.fps) + " (0..1000)");
  if (!(c.hfov_deg >= 5.0 && c.hfov_deg <= 150.0)) bad("horizontal field of view " + std::to_string(c.hfov_deg) + " deg (5..150)");
  if (!(c.exposure_s > 0.0 && c.exposure_s <= 1.0 / c.fps + 1e-12))
    bad("exposure " + std::to_string(c.exposure_s) + " s (0..1/fps)");
  if (c.motion_samples < 1 || c.motion_samples > 65) bad("motion samples " + std::to_string(c.motion_samples) + " (1..65)");
  if (c.supersample < 1 || c.supersample > 16) bad("supersample " + std::to_string(c.supersample) + " (1..16)");
  if (!(c.tag_size_mm > 0.0)) bad("tag size " + std::to_string(c.tag_size_mm) + " mm");
  if (!(c.led_radius_mm > 0.0)) bad("LED radius " + std::to_string(c.led_radius_mm) + " mm");
  if (!(c.blur_sigma_px >= 0.0 && c.blur_sigma_px <= 10.0)) bad("blur " + std::to_string(c.blur_sigma_px) + " px (0..10)");
  if (!(c.read_noise >= 0.0) || !(c.shot_noise >= 0.0)) bad("noise must be >= 0");
  return c;
}

}  // namespace

VideoSimulator::VideoSimulator(VideoSimConfig cfg)
    : cfg_(checked(std::move(cfg))),
      cam_(video_camera(cfg_)),
      model_(video_model(cfg_)),
      motion_(cam_, cfg_.beacon == BeaconKind::leds ? cfg_.leds : model_,
              [&] {
                // The simulator steps several times per frame period so the
                // exposure can be sampled: (motion_samples - 1) steps span it.
                tracker::SimulatorConfig s;
                s.motion = cfg_.motion;
                s.seed = cfg_.seed;
                s.pixels = tracker::PixelModel::exact;
                const int e = (cfg_.motion_samples - 1) / 2 * 2;
                const int k = e == 0 ? 1 : std::max(e, static_cast<int>(std::lround(e / (cfg_.exposure_s * cfg_.fps))));
                s.rate_hz = cfg_.fps * k;
                return s;
              }()),
      rng_(cfg_.seed * 0x9E3779B97F4A7C15ull + 17) {
  exposure_steps_ = (cfg_.motion_samples - 1) / 2 * 2;
  substeps_ = exposure_steps_ == 0
                  ? 1
                  : std::max(exposure_steps_, static_cast<int>(std::lround(exposure_steps_ / (cfg_.exposure_s * cfg_.fps))));
  if (cfg_.beacon == BeaconKind::apriltag) tag_ = tag_pattern(cfg_.family, cfg_.id);
  if (cfg_.background < 0.0) cfg_.background = cfg_.beacon == BeaconKind::leds ? 22.0 : 90.0;
  std::uniform_real_distribution<double> u(0.0, 2.0 * std::numbers::pi);
  for (double& p : ae_phase_) p = u(rng_);
  // Optical blur kernel: a sampled Gaussian, normalised (symmetric, so it
  // keeps every blob's centroid).
  const int r = std::max(1, static_cast<int>(std::ceil(3.0 * cfg_.blur_sigma_px)));
  kernel_.assign(static_cast<size_t>(2 * r + 1), 0.0f);
  double sum = 0.0;
  for (int i = -r; i <= r; ++i) {
    const double v = cfg_.blur_sigma_px > 0.0 ? std::exp(-0.5 * i * i / (cfg_.blur_sigma_px * cfg_.blur_sigma_px)) : (i == 0);
    kernel_[static_cast<size_t>(i + r)] = static_cast<float>(v);
    sum += v;
  }
  for (float& k : kernel_) k = static_cast<float>(k / sum);
  render_static();
}

void VideoSimulator::render_static() {
  const int w = cfg_.width, h = cfg_.height;
  const auto n = static_cast<size_t>(w) * static_cast<size_t>(h);
  scene_.assign(n, 0.0f);
  acc_.assign(n, 0.0f);
  tmp_.assign(n, 0.0f);
  const double mean = cfg_.background;
  // Smooth texture at two scales, and a few flat shapes (furniture, a door).
  const ValueNoise coarse(w, h, std::max(8.0, w / 10.0), rng_), fine(w, h, std::max(4.0, w / 60.0), rng_);
  struct Rect {
    double x0, y0, x1, y1, level;
  };
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Rect> rects;
  for (int i = 0; i < 4; ++i) {
    const double x0 = u(rng_) * w, y0 = u(rng_) * h;
    rects.push_back({x0, y0, x0 + (0.1 + 0.3 * u(rng_)) * w, y0 + (0.1 + 0.4 * u(rng_)) * h, (0.5 + u(rng_)) * mean});
  }
  const double lamp_x = 0.12 * w, lamp_y = 0.18 * h, lamp_r = 0.07 * w;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double v = mean * (1.0 + 0.35 * coarse.at(x, y) + 0.15 * fine.at(x, y));
      for (const Rect& rc : rects)
        if (x >= rc.x0 && x < rc.x1 && y >= rc.y0 && y < rc.y1) v = rc.level * (1.0 + 0.1 * fine.at(x, y));
      if (cfg_.lamp) {
        // A lamp: a disc with a one-pixel soft edge, far brighter than the sensor's range.
        const double d = std::hypot(x - lamp_x, y - lamp_y) - lamp_r;
        v += kLampRadiance * std::clamp(0.5 - d, 0.0, 1.0);
      }
      scene_[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] = static_cast<float>(std::max(0.0, v));
    }
  if (cfg_.beacon == BeaconKind::leds) {
    // LED frames add analytic (already blurred) spots on the blurred scene.
    acc_ = scene_;
    blur();
    scene_.swap(acc_);
  }
}

double VideoSimulator::gain_at(double t) const {
  if (!cfg_.auto_exposure) return 1.0;
  const double tau = 2.0 * std::numbers::pi;
  return std::exp(0.12 * std::sin(tau * t / 6.1 + ae_phase_[0]) + 0.08 * std::sin(tau * t / 2.3 + ae_phase_[1]) +
                  0.05 * std::sin(tau * t / 13.0 + ae_phase_[2]));
}

void VideoSimulator::add_leds(const Pose& pose, double weight) {
  const int w = cfg_.width, h = cfg_.height;
  const double cos_half = std::cos(model_.half_angle);
  // Beam: cos^m, half power at 60 % of the half-angle.
  const double m = std::log(0.5) / std::log(std::cos(0.6 * model_.half_angle));
  const Vec3 axis = pose.R * model_.axis;
  for (const Vec3& led : model_.leds_mm) {
    const Vec3 P = pose.apply(led);
    if (P.z() <= 1.0) continue;
    const double c = axis.dot(-P.normalized());
    if (c < cos_half) continue;
    const Vec2 px = cam_.project(P);
    // The emitting disc (variance r^2 / 4 per axis, at least half a pixel)
    // through the optics' Gaussian.
    const double r = cam_.fx * cfg_.led_radius_mm / P.z();
    const double s_src = std::max(0.5 * r, 0.5);
    const double sigma = std::sqrt(s_src * s_src + cfg_.blur_sigma_px * cfg_.blur_sigma_px);
    const double flux = weight * cfg_.led_radiance * std::numbers::pi * std::max(r, 1.0) * std::max(r, 1.0) * std::pow(c, m);
    const int reach = static_cast<int>(std::ceil(4.0 * sigma)) + 1;
    const int x0 = std::max(0, static_cast<int>(std::floor(px.x())) - reach), x1 = std::min(w - 1, static_cast<int>(std::floor(px.x())) + reach);
    const int y0 = std::max(0, static_cast<int>(std::floor(px.y())) - reach), y1 = std::min(h - 1, static_cast<int>(std::floor(px.y())) + reach);
    if (x0 > x1 || y0 > y1) continue;
    // Pixel-integrated Gaussian (pixel centres at integers): separable.
    std::array<double, 128> wx{}, wy{};
    if (x1 - x0 >= 128 || y1 - y0 >= 128) continue;
    for (int x = x0; x <= x1; ++x)
      wx[static_cast<size_t>(x - x0)] = phi((x + 0.5 - px.x()) / sigma) - phi((x - 0.5 - px.x()) / sigma);
    for (int y = y0; y <= y1; ++y)
      wy[static_cast<size_t>(y - y0)] = phi((y + 0.5 - px.y()) / sigma) - phi((y - 0.5 - px.y()) / sigma);
    for (int y = y0; y <= y1; ++y) {
      float* row = acc_.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
      const double fy = flux * wy[static_cast<size_t>(y - y0)];
      for (int x = x0; x <= x1; ++x) row[x] += static_cast<float>(fy * wx[static_cast<size_t>(x - x0)]);
    }
  }
}

void VideoSimulator::add_tag(const std::vector<Pose>& poses) {
  const TagPattern& tag = *tag_;
  const int w = cfg_.width, h = cfg_.height;
  const double cell = cfg_.tag_size_mm / tag.width_at_border;
  const double half = 0.5 * tag.total_width * cell;                 // the pattern's half side
  const double paper = half + cfg_.paper_margin_cells * cell;       // the card's half side
  // The image region the card covers during the exposure.
  double bx0 = w, by0 = h, bx1 = -1, by1 = -1;
  for (const Pose& p : poses)
    for (const auto& c : {Vec3(-paper, -paper, 0), Vec3(paper, -paper, 0), Vec3(paper, paper, 0), Vec3(-paper, paper, 0)}) {
      const Vec3 P = p.apply(c);
      if (P.z() <= 1.0) return;  // behind the camera: nothing sensible to draw
      const Vec2 q = cam_.project(P);
      bx0 = std::min(bx0, q.x());
      by0 = std::min(by0, q.y());
      bx1 = std::max(bx1, q.x());
      by1 = std::max(by1, q.y());
    }
  const int x0 = std::max(0, static_cast<int>(std::floor(bx0)) - 1), x1 = std::min(w - 1, static_cast<int>(std::ceil(bx1)) + 1);
  const int y0 = std::max(0, static_cast<int>(std::floor(by0)) - 1), y1 = std::min(h - 1, static_cast<int>(std::ceil(by1)) + 1);
  if (x0 > x1 || y0 > y1) return;
  // Inverse homographies image -> card plane (mm), one per sub-frame pose.
  // (K [r1 r2 t] maps (x, y, 1) on the card to the pixel.)
  tracker::Mat3 K;
  K << cam_.fx, 0, cam_.cx, 0, cam_.fy, cam_.cy, 0, 0, 1;
  std::vector<tracker::Mat3> inv;
  std::vector<char> front;  // printed face toward the camera; else the blank back shows
  for (const Pose& p : poses) {
    tracker::Mat3 H;
    H.col(0) = p.R.col(0);
    H.col(1) = p.R.col(1);
    H.col(2) = p.t;
    inv.push_back((K * H).inverse());
    front.push_back((p.R * Vec3(0, 0, -1)).dot(-p.t) > 0.0);
  }
  const int ss = cfg_.supersample;
  const double wgt = 1.0 / (static_cast<double>(ss * ss) * static_cast<double>(inv.size()));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const double bg = scene_[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)];
      double sum = 0.0;
      for (size_t k = 0; k < inv.size(); ++k) {
        const tracker::Mat3& Hi = inv[k];
        for (int j = 0; j < ss; ++j) {
          const double v = y + (j + 0.5) / ss - 0.5;
          for (int i = 0; i < ss; ++i) {
            const double uu = x + (i + 0.5) / ss - 0.5;
            const double X = Hi(0, 0) * uu + Hi(0, 1) * v + Hi(0, 2);
            const double Y = Hi(1, 0) * uu + Hi(1, 1) * v + Hi(1, 2);
            const double W = Hi(2, 0) * uu + Hi(2, 1) * v + Hi(2, 2);
            if (W == 0.0) {
              sum += bg;
              continue;
            }
            const double mx = X / W, my = Y / W;
            if (std::abs(mx) >= paper || std::abs(my) >= paper) {
              sum += bg;
              continue;
            }
            // Light falls off across the card (a lamp to one side).
            const double light = 1.0 + 0.25 * mx / cfg_.tag_size_mm - 0.1 * my / cfg_.tag_size_mm;
            bool white = true;
            if (front[k] && std::abs(mx) < half && std::abs(my) < half) {
              const int cx = std::clamp(static_cast<int>(std::floor((mx + half) / cell)), 0, tag.total_width - 1);
              const int cy = std::clamp(static_cast<int>(std::floor((my + half) / cell)), 0, tag.total_width - 1);
              white = tag.white(cx, cy);
            }
            sum += light * (white ? cfg_.paper_white : cfg_.ink_black);
          }
        }
      }
      acc_[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] = static_cast<float>(sum * wgt);
    }
  }
}

void VideoSimulator::blur() {
  const int w = cfg_.width, h = cfg_.height;
  const int r = static_cast<int>(kernel_.size() / 2);
  for (int y = 0; y < h; ++y) {
    const float* in = acc_.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
    float* out = tmp_.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
    for (int x = 0; x < w; ++x) {
      float s = 0.0f;
      for (int i = -r; i <= r; ++i) s += kernel_[static_cast<size_t>(i + r)] * in[std::clamp(x + i, 0, w - 1)];
      out[x] = s;
    }
  }
  for (int y = 0; y < h; ++y) {
    float* out = acc_.data() + static_cast<size_t>(y) * static_cast<size_t>(w);
    for (int x = 0; x < w; ++x) {
      float s = 0.0f;
      for (int i = -r; i <= r; ++i)
        s += kernel_[static_cast<size_t>(i + r)] *
             tmp_[static_cast<size_t>(std::clamp(y + i, 0, h - 1)) * static_cast<size_t>(w) + static_cast<size_t>(x)];
      out[x] = s;
    }
  }
}

void VideoSimulator::next(VideoFrame& frame) {
  // Exposure of frame k: simulator steps k * substeps .. + exposure_steps.
  const long first = frame_ * substeps_;
  tracker::DotFrame f;
  while (step_ < first) {
    f = motion_.next();
    ++step_;
  }
  window_.clear();
  double t_mid = 0.0;
  for (int i = 0; i <= exposure_steps_; ++i) {
    f = motion_.next();
    ++step_;
    window_.push_back(f.truth->pose);
    if (i == exposure_steps_ / 2) t_mid = f.t;
  }
  const Pose truth = window_[static_cast<size_t>(exposure_steps_ / 2)];

  acc_ = scene_;
  if (cfg_.beacon == BeaconKind::leds) {
    const double weight = 1.0 / static_cast<double>(window_.size());
    for (const Pose& p : window_) add_leds(p, weight);
  } else {
    // Motion blur needs as many sub-frames as the corners move by half
    // pixels, at most every pose of the exposure.
    double move = 0.0;
    for (const Vec3& c : model_.leds_mm) {
      const Vec3 a = window_.front().apply(c), b = window_.back().apply(c);
      if (a.z() > 1.0 && b.z() > 1.0) move = std::max(move, (cam_.project(a) - cam_.project(b)).norm());
    }
    const int n = std::clamp(1 + static_cast<int>(std::ceil(move / 0.5)), 1, static_cast<int>(window_.size()));
    std::vector<Pose> sub;
    if (n == 1) {
      sub.push_back(truth);
    } else {
      for (int i = 0; i < n; ++i)
        sub.push_back(window_[static_cast<size_t>(std::lround(static_cast<double>(i) * exposure_steps_ / (n - 1)))]);
    }
    add_tag(sub);
    blur();
  }

  frame.index = frame_;
  frame.t = t_mid;
  frame.truth = truth;
  frame.gain = gain_at(t_mid);
  // Ground-truth points: in the image and facing the camera.
  const Vec3 axis = truth.R * model_.axis;
  const double cos_half = std::cos(model_.half_angle);
  for (size_t k = 0; k < 4; ++k) {
    frame.points[k].reset();
    const Vec3 P = truth.apply(model_.leds_mm[k]);
    if (P.z() <= 1.0 || axis.dot(-P.normalized()) < cos_half) continue;
    const Vec2 px = cam_.project(P);
    if (cam_.inside(px)) frame.points[k] = px;
  }
  // The sensor: gain, shot and read noise, 8 bits.
  const auto n = acc_.size();
  frame.pixels.resize(n);
  const double g = frame.gain;
  for (size_t i = 0; i < n; ++i) {
    const double s = g * acc_[i];
    const double sd = std::sqrt(cfg_.shot_noise * std::max(s, 0.0) + cfg_.read_noise * cfg_.read_noise);
    const double v = sd > 0.0 ? s + sd * normal_(rng_) : s;
    frame.pixels[i] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  ++frame_;
}

}  // namespace earshot::webcam
