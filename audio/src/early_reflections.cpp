#include "earshot/audio/early_reflections.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace earshot::audio {
namespace {
// Tap times after the first reflection (ms at density 1), spread irregularly
// so that no two taps form a flutter; relative amplitudes fall with time.
constexpr std::array<double, EarlyReflections::kTaps> kTimeMs{0.0, 2.3, 4.1, 6.7, 8.9, 11.3, 14.2, 17.9};
constexpr std::array<double, EarlyReflections::kTaps> kLevel{1.0, 0.88, 0.8, 0.7, 0.62, 0.55, 0.47, 0.4};
}  // namespace

EarlyReflections::EarlyReflections(double sample_rate, std::size_t block) : rate_(sample_rate) {
  const auto need = static_cast<std::size_t>(std::ceil(kMaxDelayS * sample_rate)) + block + 1;
  ring_.assign(std::bit_ceil(need), 0.0f);
  mask_ = ring_.size() - 1;
  update(RoomParams{});
}

void EarlyReflections::reset() { std::fill(ring_.begin(), ring_.end(), 0.0f); }

void EarlyReflections::update(const RoomParams& p) {
  const double spread = 0.4 + 0.6 * std::clamp(p.density, 0.0, 1.0);
  double energy = 0.0;
  for (double l : kLevel) energy += l * l;
  const double norm = std::clamp(p.reflections_gain, 0.0, 3.16) / std::sqrt(energy);
  const double first = std::clamp(p.reflections_delay_s, 0.0, 0.3);
  for (std::size_t i = 0; i < kTaps; ++i) {
    const double t = first + kTimeMs[i] * 1e-3 * spread;
    taps_[i].delay = std::min(ring_.size() - 1, static_cast<std::size_t>(std::lround(t * rate_)));
    // Odd taps lean left, even taps right (0.9 / 0.44 keeps each tap's energy
    // at about its level squared); signs alternate in pairs.
    const double a = kLevel[i] * norm * ((i / 2) % 2 == 0 ? 1.0 : -1.0);
    const bool lean_left = i % 2 == 0;
    taps_[i].left = static_cast<float>(a * (lean_left ? 0.9 : 0.44));
    taps_[i].right = static_cast<float>(a * (lean_left ? 0.44 : -0.9));
  }
}

void EarlyReflections::process(std::span<const float> in, std::span<float> out_left, std::span<float> out_right) {
  for (std::size_t n = 0; n < in.size(); ++n) {
    ring_[write_] = in[n];
    float l = 0.0f, r = 0.0f;
    for (const auto& t : taps_) {
      const float x = ring_[(write_ - t.delay) & mask_];
      l += t.left * x;
      r += t.right * x;
    }
    out_left[n] += l;
    out_right[n] += r;
    write_ = (write_ + 1) & mask_;
  }
}

}  // namespace earshot::audio
