#include "earshot/audio/hrtf_spectra.hpp"

#include <algorithm>
#include <stdexcept>

#include "earshot/audio/half_float.hpp"
#include "earshot/audio/real_fft.hpp"
#include "earshot/audio/spectral_kernels.hpp"

namespace earshot::audio {

HrtfSpectra::HrtfSpectra(const hrtf::HrtfSet& set, std::size_t block)
    : block_(block),
      parts_(std::max<std::size_t>(1, block ? (set.filter_length() + block - 1) / block : 1)),
      measurements_(set.measurement_count()) {
  if (block == 0) throw std::invalid_argument("HrtfSpectra: block must be > 0");
  const std::size_t P = 2 * stride(), M = set.measurement_count();
  head_.assign(M * 2 * P, 0.0f);
  tail_.assign(M * 2 * (parts_ - 1) * P, 0);
  RealFft fft(2 * block);
  std::vector<float> padded(2 * block);
  std::vector<std::complex<float>> bins_out(bins());
  std::vector<float> planar(P, 0.0f);
  for (std::size_t m = 0; m < M; ++m)
    for (hrtf::Ear ear : {hrtf::Ear::left, hrtf::Ear::right}) {
      const auto ir = set.filter(m, ear);
      const std::size_t lane = 2 * m + static_cast<std::size_t>(ear);
      for (std::size_t p = 0; p < parts_; ++p) {
        std::fill(padded.begin(), padded.end(), 0.0f);
        const std::size_t from = p * block;
        if (from < ir.size()) std::copy_n(ir.begin() + static_cast<long>(from), std::min(block, ir.size() - from), padded.begin());
        fft.forward(padded, bins_out);
        kernels::to_planar(bins_out.data(), bins(), planar.data(), stride());
        if (p == 0)
          std::copy(planar.begin(), planar.end(), head_.data() + lane * P);
        else
          std::transform(planar.begin(), planar.end(), tail_.data() + (lane * (parts_ - 1) + p - 1) * P, float_to_half);
      }
    }
}

std::span<const float> HrtfSpectra::head(std::size_t m, hrtf::Ear ear) const {
  const std::size_t P = 2 * stride();
  return {head_.data() + (2 * m + static_cast<std::size_t>(ear)) * P, P};
}

std::span<const std::uint16_t> HrtfSpectra::tail(std::size_t m, hrtf::Ear ear) const {
  const std::size_t n = (parts_ - 1) * 2 * stride();
  return {tail_.data() + (2 * m + static_cast<std::size_t>(ear)) * n, n};
}

}  // namespace earshot::audio
