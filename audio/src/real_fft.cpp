#include "earshot/audio/real_fft.hpp"

#include <kissfft/kiss_fftr.h>

#include <stdexcept>

namespace earshot::audio {

struct RealFft::Plans {
  kiss_fftr_cfg fwd = nullptr, inv = nullptr;
  ~Plans() {
    kiss_fftr_free(fwd);
    kiss_fftr_free(inv);
  }
};

static_assert(sizeof(kiss_fft_cpx) == sizeof(std::complex<float>), "kiss_fft_cpx must match std::complex<float>");

RealFft::RealFft(std::size_t size) : size_(size), plans_(std::make_unique<Plans>()) {
  if (size < 2 || size % 2) throw std::invalid_argument("RealFft: size must be even and >= 2");
  plans_->fwd = kiss_fftr_alloc(static_cast<int>(size), 0, nullptr, nullptr);
  plans_->inv = kiss_fftr_alloc(static_cast<int>(size), 1, nullptr, nullptr);
  if (!plans_->fwd || !plans_->inv) throw std::bad_alloc();
}

RealFft::~RealFft() = default;
RealFft::RealFft(RealFft&&) noexcept = default;
RealFft& RealFft::operator=(RealFft&&) noexcept = default;

void RealFft::forward(std::span<const float> time, std::span<std::complex<float>> spectrum) const {
  kiss_fftr(plans_->fwd, time.data(), reinterpret_cast<kiss_fft_cpx*>(spectrum.data()));
}

void RealFft::inverse(std::span<const std::complex<float>> spectrum, std::span<float> time) const {
  kiss_fftri(plans_->inv, reinterpret_cast<const kiss_fft_cpx*>(spectrum.data()), time.data());
  const float scale = 1.0f / static_cast<float>(size_);
  for (std::size_t i = 0; i < size_; ++i) time[i] *= scale;
}

}  // namespace earshot::audio
