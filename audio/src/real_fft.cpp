#include "earshot/audio/real_fft.hpp"

extern "C" {
#include <libavutil/tx.h>
}
#include <kissfft/kiss_fftr.h>

#include <algorithm>
#include <cstdint>
#include <new>
#include <stdexcept>

#include <cmath>
#include <numbers>

#include "earshot/audio/aligned_vector.hpp"
#include "earshot/audio/spectral_kernels.hpp"

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
  // forward_planar: the complex FFT of size / 2 (into `spectrum`), the
  // split's twiddles c, s and the bins' signs.
  AVTXContext* half = nullptr;
  av_tx_fn half_fn = nullptr;
  AlignedVector<float> c, s, plus, alternating;
  ~Plans() {
    av_tx_uninit(&fwd);
    av_tx_uninit(&inv);
    av_tx_uninit(&half);
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
  plans_->spectrum.assign(bins() + 1, {});  // forward_planar's scratch on every path
  if (plans_->fwd) {
    plans_->time.assign(size + 2, 0.0f);
    const std::size_t M = size / 2;
    if (M >= 16 && av_tx_init(&plans_->half, &plans_->half_fn, AV_TX_FLOAT_FFT, 0, static_cast<int>(M), &one, 0) < 0)
      throw std::bad_alloc();
    for (auto* v : {&plans_->c, &plans_->s, &plans_->plus, &plans_->alternating}) v->assign(M + 1, 0.0f);
    for (std::size_t k = 0; k <= M; ++k) {
      const double a = std::numbers::pi * static_cast<double>(k) / static_cast<double>(M);
      plans_->c[k] = static_cast<float>(0.5 * std::cos(a));
      plans_->s[k] = static_cast<float>(0.5 * std::sin(a));
      plans_->plus[k] = 1.0f;
      plans_->alternating[k] = (k & 1) ? -1.0f : 1.0f;
    }
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

void RealFft::forward_planar(std::span<const float> time, float* out, std::size_t stride, bool odd_negated) const {
  Plans& p = *plans_;
  if (!p.half) {  // KissFFT sizes (and the smallest): the plain transform, then the layout
    forward(time, std::span(p.spectrum.data(), bins()));
    if (odd_negated)
      kernels::to_planar_odd_negated(p.spectrum.data(), bins(), out, stride);
    else
      kernels::to_planar(p.spectrum.data(), bins(), out, stride);
    return;
  }
  const std::size_t M = size_ / 2;
  const float* in = time.data();
  if (!aligned(in) || time.size() < size_) {
    std::copy_n(time.begin(), size_, p.time.begin());
    in = p.time.data();
  }
  // x viewed as M complex values x_2n + i x_2n+1; av_tx reads its input only.
  p.half_fn(p.half, p.spectrum.data(), const_cast<float*>(in), sizeof(std::complex<float>));
  p.spectrum[M] = p.spectrum[0];
  const float* sign = odd_negated ? p.alternating.data() : p.plus.data();
  kernels::real_spectrum(p.spectrum.data(), M, p.c.data(), p.s.data(), sign, out, stride);
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
