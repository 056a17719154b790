#include "earshot/audio/ambisonics/encoder.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"
#include "earshot/audio/spectral_kernels.hpp"

namespace earshot::ambisonics {

Encoder::Encoder(int order, std::size_t block) : order_(order), block_(block) {
  if (order < 0 || order > kMaxOrder) throw std::invalid_argument("Encoder: order outside 0..7");
  if (block == 0) throw std::invalid_argument("Encoder: block must be > 0");
  gains_.assign(channel_count(order), 0.0f);
  target_ = gains_;
  ramp_.resize(block);
  for (std::size_t i = 0; i < block; ++i) ramp_[i] = float(double(i + 1) / double(block));
}

void Encoder::update(const Vec3& direction, float gain) {
  const double n = norm(direction);
  if (!std::isfinite(n) || !(n > 1e-12) || !std::isfinite(gain)) return;
  real_sh(order_, Vec3{direction[0] / n, direction[1] / n, direction[2] / n}, std::span<float>(target_));
  for (float& g : target_) g *= gain;
  if (!started_) {
    gains_ = target_;
    started_ = true;
  }
}

void Encoder::process(std::span<const float> in, std::span<float> bus) {
  const std::size_t B = block_;
  if (in.size() < B || bus.size() < gains_.size() * B) return;
  for (std::size_t c = 0; c < gains_.size(); ++c) {
    float* y = bus.data() + c * B;
    const float a = gains_[c], d = target_[c] - gains_[c];
    // The renderer's gain-curve kernel (AVX2 where the CPU has it): the
    // tier runs this for every source and channel.
    if (a != 0.0f || d != 0.0f) audio::kernels::add_shaped(in.data(), a, d, 0.0f, ramp_.data(), ramp_.data(), y, B);
    gains_[c] = target_[c];
  }
}

}  // namespace earshot::ambisonics
