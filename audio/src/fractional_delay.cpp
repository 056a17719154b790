#include "earshot/audio/fractional_delay.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace earshot::audio {

FractionalDelay::FractionalDelay(std::size_t block, double max_delay_samples)
    : max_delay_(std::max(kMinDelay, max_delay_samples)) {
  const std::size_t need = block + static_cast<std::size_t>(std::ceil(max_delay_)) + 4;
  ring_.assign(std::bit_ceil(need), 0.0f);
  mask_ = ring_.size() - 1;
}

void FractionalDelay::reset() {
  std::fill(ring_.begin(), ring_.end(), 0.0f);
  delay_ = -1.0;
}

void FractionalDelay::process(std::span<const float> in, std::span<float> out, double delay_samples) {
  const double target = std::clamp(std::isfinite(delay_samples) ? delay_samples : kMinDelay, kMinDelay, max_delay_);
  const double start = delay_ < 0.0 ? target : delay_;
  const std::size_t n = in.size();
  const double step = (target - start) / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    ring_[write_] = in[i];
    const double d = start + step * static_cast<double>(i + 1);
    // Read position write_ - d, between samples x1 = floor and x2 = x1 + 1.
    const double ipart = std::floor(d);
    const double f = 1.0 - (d - ipart);  // fraction from x1 towards x2
    const std::size_t base = write_ - static_cast<std::size_t>(ipart) - 1;  // x1 (wraps via mask)
    const float x0 = ring_[(base - 1) & mask_], x1 = ring_[base & mask_];
    const float x2 = ring_[(base + 1) & mask_], x3 = ring_[(base + 2) & mask_];
    // 4-point, 3rd-order Lagrange at position f in [0, 1) from x1.
    const double c0 = -f * (f - 1) * (f - 2) / 6.0;
    const double c1 = (f + 1) * (f - 1) * (f - 2) / 2.0;
    const double c2 = -(f + 1) * f * (f - 2) / 2.0;
    const double c3 = (f + 1) * f * (f - 1) / 6.0;
    out[i] = static_cast<float>(c0 * x0 + c1 * x1 + c2 * x2 + c3 * x3);
    write_ = (write_ + 1) & mask_;
  }
  delay_ = target;
}

}  // namespace earshot::audio
