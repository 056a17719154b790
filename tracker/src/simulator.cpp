#include "earshot/tracker/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace earshot::tracker {
namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

std::optional<PixelModel> pixel_model_from(std::string_view name) {
  if (name == "exact") return PixelModel::exact;
  if (name == "integer") return PixelModel::integer;
  if (name == "quantize8") return PixelModel::quantize8;
  if (name == "gaussian") return PixelModel::gaussian;
  return std::nullopt;
}

Simulator::Simulator(const Camera& cam, const LedModel& model, SimulatorConfig cfg)
    : cam_(cam), model_(model), cfg_(cfg), rng_(cfg.seed) {
  // Start in the middle of the walk's box, facing the camera.
  s_ << 0.0, 0.0, 0.5 * (cfg_.z_min_mm + cfg_.z_max_mm), 0.0, 0.0, 0.0;
}

void Simulator::step(double dt) {
  // Each coordinate follows an Ornstein-Uhlenbeck velocity (correlation time
  // one second) whose stationary RMS is the configured speed, and reflects at
  // the walk's bounds.
  const double k = 1.0;
  const double z = s_[2];
  const double x_max = cfg_.lateral_fraction * z * (cam_.cx / cam_.fx);
  const double y_max = cfg_.lateral_fraction * z * (cam_.cy / cam_.fy);
  const std::array<double, 6> lo{-x_max, -y_max, cfg_.z_min_mm, -cfg_.yaw_max_deg * kDeg,
                                 -cfg_.pitch_max_deg * kDeg, -cfg_.roll_max_deg * kDeg};
  const std::array<double, 6> hi{x_max, y_max, cfg_.z_max_mm, cfg_.yaw_max_deg * kDeg,
                                 cfg_.pitch_max_deg * kDeg, cfg_.roll_max_deg * kDeg};
  for (int i = 0; i < 6; ++i) {
    const double rms = i < 3 ? cfg_.speed_mm_s : cfg_.angular_speed_deg_s * kDeg;
    const double sigma = rms * std::sqrt(2.0 * k);
    v_[i] += -k * v_[i] * dt + sigma * std::sqrt(dt) * normal_(rng_);
    s_[i] += v_[i] * dt;
    const auto u = static_cast<size_t>(i);
    if (i == 5 && cfg_.roll_max_deg >= 180.0) {  // full circle: wrap
      s_[i] = std::remainder(s_[i], 2.0 * std::numbers::pi);
      continue;
    }
    if (s_[i] > hi[u]) {
      s_[i] = 2.0 * hi[u] - s_[i];
      v_[i] = -std::abs(v_[i]);
    } else if (s_[i] < lo[u]) {
      s_[i] = 2.0 * lo[u] - s_[i];
      v_[i] = std::abs(v_[i]);
    }
    s_[i] = std::clamp(s_[i], lo[u], hi[u]);
  }
}

double Simulator::round_pixel(double v) {
  switch (cfg_.pixels) {
    case PixelModel::exact: return v;
    case PixelModel::integer: return std::floor(v + 0.5);
    case PixelModel::quantize8: return 8.0 * std::floor(v / 8.0 + 0.5);
    case PixelModel::gaussian: return v + cfg_.noise_px * normal_(rng_);
  }
  return v;
}

DotFrame Simulator::observe(const Pose& pose, double t) {
  DotFrame f;
  f.t = t;
  GroundTruth gt;
  gt.pose = pose;

  std::array<std::optional<Vec2>, 4> led_px;
  const double cos_half = std::cos(model_.half_angle);
  for (size_t l = 0; l < 4; ++l) {
    if (dropout_left_[l] > 0) {
      --dropout_left_[l];
      continue;
    }
    if (cfg_.dropout_rate > 0.0 && uniform_(rng_) < cfg_.dropout_rate) {
      dropout_left_[l] = 1 + static_cast<int>(uniform_(rng_) * 10.0);
      continue;
    }
    const Vec3 P = pose.apply(model_.leds_mm[l]);
    if (P.z() <= 1.0) continue;
    const Vec3 axis = pose.R * model_.axis;
    if (axis.dot(-P.normalized()) < cos_half) continue;  // turned away beyond the beam
    Vec2 px = cam_.project(P);
    px = {round_pixel(px.x()), round_pixel(px.y())};
    if (!cam_.inside(px)) continue;
    led_px[l] = px;
  }

  // Slots: a dot keeps its slot while visible; a new dot takes a random free one.
  std::array<int, kSlots> slots = slot_led_;
  for (auto& s : slots)
    if (s > 0 && !led_px[static_cast<size_t>(s - 1)]) s = 0;
  if (stray_left_ > 0) --stray_left_;
  for (auto& s : slots)
    if (s == -1 && stray_left_ == 0) s = 0;
  auto place = [&](int who) {
    std::array<int, kSlots> free{};
    int nfree = 0;
    for (int s = 0; s < kSlots; ++s)
      if (slots[static_cast<size_t>(s)] == 0) free[static_cast<size_t>(nfree++)] = s;
    if (nfree == 0) return false;
    const int pick = free[static_cast<size_t>(std::min(nfree - 1, static_cast<int>(uniform_(rng_) * nfree)))];
    slots[static_cast<size_t>(pick)] = who;
    return true;
  };
  for (int l = 0; l < 4; ++l) {
    if (!led_px[static_cast<size_t>(l)]) continue;
    if (std::find(slots.begin(), slots.end(), l + 1) == slots.end()) place(l + 1);
  }
  if (cfg_.stray_rate > 0.0 && stray_left_ == 0 && uniform_(rng_) < cfg_.stray_rate) {
    // A reflection somewhere near the beacon, staying a few frames.
    const Vec2 c = cam_.project(pose.t);
    stray_px_ = c + Vec2((uniform_(rng_) - 0.5) * 300.0, (uniform_(rng_) - 0.5) * 300.0);
    stray_px_ = {std::floor(stray_px_.x() + 0.5), std::floor(stray_px_.y() + 0.5)};
    if (cam_.inside(stray_px_) && place(-1)) stray_left_ = 1 + static_cast<int>(uniform_(rng_) * 20.0);
  }
  slot_led_ = slots;
  for (size_t s = 0; s < kSlots; ++s) {
    if (slots[s] > 0) f.slots[s] = led_px[static_cast<size_t>(slots[s] - 1)];
    if (slots[s] == -1) f.slots[s] = stray_px_;
  }
  gt.slot_led = slots;
  f.truth = gt;
  return f;
}

DotFrame Simulator::next() {
  const double dt = 1.0 / cfg_.rate_hz;
  if (frame_ > 0) step(dt);
  const double t = static_cast<double>(frame_) * dt;
  ++frame_;
  const Pose pose{rotation_from_ypr(s_[3], s_[4], s_[5]), s_.head<3>()};
  return observe(pose, t);
}

}  // namespace earshot::tracker
