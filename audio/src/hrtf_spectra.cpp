#include "earshot/audio/hrtf_spectra.hpp"

#include <algorithm>
#include <stdexcept>

#include "earshot/audio/real_fft.hpp"
#include "earshot/audio/spectral_kernels.hpp"

namespace earshot::audio {

HrtfSpectra::HrtfSpectra(const hrtf::HrtfSet& set, std::size_t block)
    : block_(block),
      parts_(std::max<std::size_t>(1, block ? (set.filter_length() + block - 1) / block : 1)),
      measurements_(set.measurement_count()) {
  if (block == 0) throw std::invalid_argument("HrtfSpectra: block must be > 0");
  const std::size_t per_ear = parts_ * 2 * stride();
  data_.assign(set.measurement_count() * 2 * per_ear, 0.0f);
  RealFft fft(2 * block);
  std::vector<float> padded(2 * block);
  std::vector<std::complex<float>> bins_out(bins());
  for (std::size_t m = 0; m < set.measurement_count(); ++m)
    for (hrtf::Ear ear : {hrtf::Ear::left, hrtf::Ear::right}) {
      const auto ir = set.filter(m, ear);
      float* out = data_.data() + (2 * m + static_cast<std::size_t>(ear)) * per_ear;
      for (std::size_t p = 0; p < parts_; ++p) {
        std::fill(padded.begin(), padded.end(), 0.0f);
        const std::size_t from = p * block;
        if (from < ir.size()) std::copy_n(ir.begin() + static_cast<long>(from), std::min(block, ir.size() - from), padded.begin());
        fft.forward(padded, bins_out);
        kernels::to_planar(bins_out.data(), bins(), out + p * 2 * stride(), stride());
      }
    }
}

std::span<const float> HrtfSpectra::spectrum(std::size_t m, hrtf::Ear ear) const {
  const std::size_t per_ear = parts_ * 2 * stride();
  return {data_.data() + (2 * m + static_cast<std::size_t>(ear)) * per_ear, per_ear};
}

}  // namespace earshot::audio
