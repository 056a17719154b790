#include "earshot/audio/ambisonics/scene_rotator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"

namespace earshot::ambisonics {

SceneRotator::SceneRotator(int order, std::size_t block)
    : order_(order), channels_(channel_count(order)), block_(block), rotation_(order) {
  if (block == 0) throw std::invalid_argument("SceneRotator: block must be > 0");
  std::size_t entries = 0;
  for (int l = 0; l <= order; ++l) entries += static_cast<std::size_t>((2 * l + 1) * (2 * l + 1));
  from_.assign(entries, 0.0f);
  to_.assign(entries, 0.0f);
  ramp_.resize(block);
  for (std::size_t i = 0; i < block; ++i) ramp_[i] = float(double(i + 1) / double(block));
  load(kIdentityQuat, from_);
  to_ = from_;
}

void SceneRotator::load(const Quat& q, std::vector<float>& dense) {
  rotation_.set(field_rotation_for_listener(q));
  std::size_t k = 0;
  for (int l = 0; l <= order_; ++l)
    for (double v : rotation_.block(l)) dense[k++] = static_cast<float>(v);
}

void SceneRotator::update(const Quat& listener_orientation) {
  const auto q = normalised(listener_orientation);
  if (!q) return;
  load(*q, to_);
  if (!started_) {
    std::copy(to_.begin(), to_.end(), from_.begin());
    started_ = true;
  }
  moving_ = !std::equal(from_.begin(), from_.end(), to_.begin());
}

void SceneRotator::reset(const Quat& listener_orientation) {
  started_ = false;
  update(listener_orientation);
}

void SceneRotator::process(std::span<const float> in, std::span<float> out) {
  const std::size_t B = block_;
  if (in.size() < channels_ * B || out.size() < channels_ * B) return;
  std::fill_n(out.begin(), channels_ * B, 0.0f);
  const float* r = ramp_.data();
  std::size_t k = 0;
  for (int l = 0; l <= order_; ++l) {
    const auto first = static_cast<std::size_t>(l * l), size = static_cast<std::size_t>(2 * l + 1);
    for (std::size_t i = 0; i < size; ++i) {
      float* y = out.data() + (first + i) * B;
      for (std::size_t j = 0; j < size; ++j, ++k) {
        const float* x = in.data() + (first + j) * B;
        const float a = from_[k], d = to_[k] - from_[k];
        if (moving_ && d != 0.0f) {
          for (std::size_t n = 0; n < B; ++n) y[n] += (a + d * r[n]) * x[n];
        } else if (a != 0.0f) {
          for (std::size_t n = 0; n < B; ++n) y[n] += a * x[n];
        }
      }
    }
  }
  if (moving_) {
    std::copy(to_.begin(), to_.end(), from_.begin());
    moving_ = false;
  }
}

}  // namespace earshot::ambisonics
