#include "earshot/audio/real_fft.hpp"

extern "C" {
#include <libavutil/tx.h>
}
#include <kissfft/kiss_fftr.h>

#include <algorithm>
#include <cstdint>
#include <new>
#include <stdexcept>

#include "earshot/audio/aligned_vector.hpp"

namespace earshot::audio {
namespace {
bool aligned(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % 32 == 0; }
// av_tx (FFmpeg 5.1) has SIMD code for powers of two up to 2^17 and falls
// back to an O(n^2) transform beyond (or for awkward factors): those sizes,
// used only by analysis of whole files, go to KissFFT.
bool av_tx_is_fast(std::size_t n) { return n >= 16 && n <= (std::size_t{1} << 17) && (n & (n - 1)) == 0; }
}  // namespace

struct RealFft::Plans {
  AVTXContext* fwd = nullptr;
  AVTXContext* inv = nullptr;
  av_tx_fn fwd_fn = nullptr, inv_fn = nullptr;
  kiss_fftr_cfg kiss_fwd = nullptr, kiss_inv = nullptr;  // the other sizes
  // Aligned scratch: the transform's input and output (the inverse
  // overwrites its input, so a const spectrum is copied here first).
  mutable AlignedVector<float> time;
  mutable AlignedVector<std::complex<float>> spectrum;
  ~Plans() {
    av_tx_uninit(&fwd);
    av_tx_uninit(&inv);
    kiss_fftr_free(kiss_fwd);
    kiss_fftr_free(kiss_inv);
  }
};

RealFft::RealFft(std::size_t size) : size_(size), plans_(std::make_unique<Plans>()) {
  if (size < 2 || size % 2) throw std::invalid_argument("RealFft: size must be even and >= 2");
  const float one = 1.0f, inv_scale = 1.0f / static_cast<float>(size);
  const int len = static_cast<int>(size);
  if (av_tx_is_fast(size)) {
    if (av_tx_init(&plans_->fwd, &plans_->fwd_fn, AV_TX_FLOAT_RDFT, 0, len, &one, 0) < 0 ||
        av_tx_init(&plans_->inv, &plans_->inv_fn, AV_TX_FLOAT_RDFT, 1, len, &inv_scale, 0) < 0)
      throw std::bad_alloc();
  } else {
    plans_->kiss_fwd = kiss_fftr_alloc(len, 0, nullptr, nullptr);
    plans_->kiss_inv = kiss_fftr_alloc(len, 1, nullptr, nullptr);
    if (!plans_->kiss_fwd || !plans_->kiss_inv) throw std::bad_alloc();
  }
  if (plans_->fwd) {
    plans_->time.assign(size + 2, 0.0f);
    plans_->spectrum.assign(bins() + 1, {});
  }
}

RealFft::~RealFft() = default;
RealFft::RealFft(RealFft&&) noexcept = default;
RealFft& RealFft::operator=(RealFft&&) noexcept = default;

void RealFft::forward(std::span<const float> time, std::span<std::complex<float>> spectrum) const {
  Plans& p = *plans_;
  if (p.kiss_fwd) {
    kiss_fftr(p.kiss_fwd, time.data(), reinterpret_cast<kiss_fft_cpx*>(spectrum.data()));
    return;
  }
  float* in = p.time.data();
  if (aligned(time.data()) && time.size() >= size_) {
    in = const_cast<float*>(time.data());  // av_tx reads the forward input only
  } else {
    std::copy_n(time.begin(), size_, p.time.begin());
  }
  if (aligned(spectrum.data())) {
    p.fwd_fn(p.fwd, spectrum.data(), in, sizeof(float));
  } else {
    p.fwd_fn(p.fwd, p.spectrum.data(), in, sizeof(float));
    std::copy_n(p.spectrum.begin(), bins(), spectrum.begin());
  }
}

void RealFft::inverse(std::span<const std::complex<float>> spectrum, std::span<float> time) const {
  if (plans_->kiss_inv) {
    inverse_destroying({const_cast<std::complex<float>*>(spectrum.data()), spectrum.size()}, time);  // KissFFT keeps its input
    return;
  }
  std::copy_n(spectrum.begin(), bins(), plans_->spectrum.begin());
  inverse_destroying(plans_->spectrum, time);
}

void RealFft::inverse_destroying(std::span<std::complex<float>> spectrum, std::span<float> time) const {
  Plans& p = *plans_;
  if (p.kiss_inv) {
    kiss_fftri(p.kiss_inv, reinterpret_cast<const kiss_fft_cpx*>(spectrum.data()), time.data());
    const float scale = 1.0f / static_cast<float>(size_);
    for (std::size_t i = 0; i < size_; ++i) time[i] *= scale;
    return;
  }
  std::complex<float>* in = spectrum.data();
  if (!aligned(in)) {
    std::copy_n(spectrum.begin(), bins(), p.spectrum.begin());
    in = p.spectrum.data();
  }
  if (aligned(time.data())) {
    p.inv_fn(p.inv, time.data(), in, sizeof(float));
  } else {
    p.inv_fn(p.inv, p.time.data(), in, sizeof(float));
    std::copy_n(p.time.begin(), size_, time.begin());
  }
}

}  // namespace earshot::audio
