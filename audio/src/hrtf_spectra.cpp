#include "earshot/audio/hrtf_spectra.hpp"

#include <algorithm>
#include <stdexcept>

#include "earshot/audio/real_fft.hpp"

namespace earshot::audio {

HrtfSpectra::HrtfSpectra(const hrtf::HrtfSet& set, std::size_t block)
    : block_(block), parts_(std::max<std::size_t>(1, (set.filter_length() + block - 1) / block)) {
  if (block == 0) throw std::invalid_argument("HrtfSpectra: block must be > 0");
  const std::size_t per_ear = parts_ * bins();
  data_.resize(set.measurement_count() * 2 * per_ear);
  RealFft fft(2 * block);
  std::vector<float> padded(2 * block);
  for (std::size_t m = 0; m < set.measurement_count(); ++m)
    for (hrtf::Ear ear : {hrtf::Ear::left, hrtf::Ear::right}) {
      const auto ir = set.filter(m, ear);
      std::complex<float>* out = data_.data() + (2 * m + static_cast<std::size_t>(ear)) * per_ear;
      for (std::size_t p = 0; p < parts_; ++p) {
        std::fill(padded.begin(), padded.end(), 0.0f);
        const std::size_t from = p * block;
        if (from < ir.size()) std::copy_n(ir.begin() + static_cast<long>(from), std::min(block, ir.size() - from), padded.begin());
        fft.forward(padded, std::span(out + p * bins(), bins()));
      }
    }
}

std::span<const std::complex<float>> HrtfSpectra::spectrum(std::size_t m, hrtf::Ear ear) const {
  const std::size_t per_ear = parts_ * bins();
  return {data_.data() + (2 * m + static_cast<std::size_t>(ear)) * per_ear, per_ear};
}

double HrtfSpectra::energy(std::span<const std::complex<float>> spectra) const {
  // sum x^2 = (|X_0|^2 + |X_N/2|^2 + 2 sum_{0<k<N/2} |X_k|^2) / N, N = 2B, per partition.
  const std::size_t n = bins();
  double e = 0.0;
  for (std::size_t p = 0; p < parts_; ++p) {
    const std::complex<float>* x = spectra.data() + p * n;
    double inner = 0.0;
    for (std::size_t k = 1; k + 1 < n; ++k) inner += std::norm(x[k]);
    e += std::norm(x[0]) + std::norm(x[n - 1]) + 2.0 * inner;
  }
  return e / static_cast<double>(2 * block_);
}

}  // namespace earshot::audio
