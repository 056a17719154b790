// A real FFT of one size, planned at construction so that forward/inverse
// never allocate. Spectra hold size/2 + 1 complex bins, unscaled forward,
// inverse scaled by 1/size (so inverse(forward(x)) = x).
//
// Backed by FFmpeg's libavutil av_tx (LGPL, runtime-dispatched SIMD) for
// powers of two up to 2^17: for the renderer's 256-point transforms it is
// about three times faster than KissFFT on this machine, and the FFTs are a
// large part of a source's cost. Other sizes (av_tx 5.1 has no fast code
// for them) use KissFFT.
// Buffers aligned to 32 bytes (AlignedVector) take the fast path; others are
// copied through aligned scratch space first.
#pragma once

#include <complex>
#include <memory>
#include <span>

namespace earshot::audio {

class RealFft {
 public:
  explicit RealFft(std::size_t size);  ///< size must be even and >= 2
  ~RealFft();
  RealFft(RealFft&&) noexcept;
  RealFft& operator=(RealFft&&) noexcept;

  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] std::size_t bins() const { return size_ / 2 + 1; }
  /// time (size) -> spectrum (bins)
  void forward(std::span<const float> time, std::span<std::complex<float>> spectrum) const;
  /// time (size) -> spectrum (bins) in the planar layout: real parts at
  /// out[0..bins), imaginary parts at out[stride..stride + bins); padding
  /// left as it is. odd_negated flips the sign of the odd bins (the spectrum
  /// of the input rotated by size / 2). For powers of two it runs a complex
  /// FFT of size / 2 and its own vectorised split into the real signal's
  /// bins (av_tx 5.1's real transform does that step in scalar code, which
  /// took half of the transform's time), and needs no to_planar copy.
  void forward_planar(std::span<const float> time, float* out, std::size_t stride, bool odd_negated) const;
  /// spectrum (bins) -> time (size), scaled by 1/size so inverse(forward(x)) = x
  void inverse(std::span<const std::complex<float>> spectrum, std::span<float> time) const;
  /// As inverse(), but may overwrite `spectrum` (saves a copy on hot paths).
  void inverse_destroying(std::span<std::complex<float>> spectrum, std::span<float> time) const;

 private:
  struct Plans;
  std::size_t size_;
  std::unique_ptr<Plans> plans_;
};

}  // namespace earshot::audio
