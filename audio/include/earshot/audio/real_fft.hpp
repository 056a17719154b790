// A real FFT of one size (KissFFT, BSD), planned at construction so that
// forward/inverse never allocate. Spectra hold size/2 + 1 complex bins.
#pragma once

#include <complex>
#include <memory>
#include <span>

namespace earshot::audio {

class RealFft {
 public:
  explicit RealFft(std::size_t size);  ///< size must be even
  ~RealFft();
  RealFft(RealFft&&) noexcept;
  RealFft& operator=(RealFft&&) noexcept;

  [[nodiscard]] std::size_t size() const { return size_; }
  [[nodiscard]] std::size_t bins() const { return size_ / 2 + 1; }
  /// time (size) -> spectrum (bins)
  void forward(std::span<const float> time, std::span<std::complex<float>> spectrum) const;
  /// spectrum (bins) -> time (size), scaled by 1/size so inverse(forward(x)) = x
  void inverse(std::span<const std::complex<float>> spectrum, std::span<float> time) const;

 private:
  struct Plans;
  std::size_t size_;
  std::unique_ptr<Plans> plans_;
};

}  // namespace earshot::audio
