#include "earshot/audio/binaural_bus.hpp"

#include <algorithm>
#include <stdexcept>

#include "earshot/audio/hrtf_spectra.hpp"
#include "earshot/audio/spectral_kernels.hpp"

namespace earshot::audio {

BinauralBus::BinauralBus(std::size_t block) : block_(block), fft_(2 * std::max<std::size_t>(block, 1)) {
  if (block == 0) throw std::invalid_argument("BinauralBus: block must be > 0");
  for (auto& ear : acc_)
    for (auto& a : ear) a.assign(2 * partition_stride(block), 0.0f);
  spectrum_.assign(partition_stride(block), {});
  time_.assign(2 * block, 0.0f);
  ramp_.resize(block);
  for (std::size_t i = 0; i < block; ++i) ramp_[i] = (static_cast<float>(i) + 1.0f) / static_cast<float>(block);
}

void BinauralBus::clear() {
  for (std::size_t ear = 0; ear < 2; ++ear)
    for (std::size_t f = 0; f < 3; ++f)
      if (used_[ear][f]) {
        std::fill(acc_[ear][f].begin(), acc_[ear][f].end(), 0.0f);
        used_[ear][f] = false;
      }
}

float* BinauralBus::accumulator(std::size_t ear, Fade fade) {
  const auto f = static_cast<std::size_t>(fade);
  used_[ear][f] = true;
  return acc_[ear][f].data();
}

void BinauralBus::mix_into(std::span<float> left, std::span<float> right) {
  const std::size_t B = block_;
  for (std::size_t ear = 0; ear < 2; ++ear) {
    float* out = ear == 0 ? left.data() : right.data();
    for (std::size_t f = 0; f < 3; ++f) {
      if (!used_[ear][f]) continue;
      kernels::to_interleaved(acc_[ear][f].data(), partition_stride(B), spectrum_.data(), B + 1);
      fft_.inverse_destroying(std::span(spectrum_).first(B + 1), time_);
      const float* y = time_.data() + B;             // overlap-save: the last B samples are the block
      if (f == static_cast<std::size_t>(Fade::steady)) {
        for (std::size_t i = 0; i < B; ++i) out[i] += y[i];
      } else if (f == static_cast<std::size_t>(Fade::in)) {
        for (std::size_t i = 0; i < B; ++i) out[i] += ramp_[i] * y[i];
      } else {
        for (std::size_t i = 0; i < B; ++i) out[i] += (1.0f - ramp_[i]) * y[i];
      }
    }
  }
}

}  // namespace earshot::audio
