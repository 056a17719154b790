#include "earshot/audio/hrtf_spectra.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "earshot/audio/real_fft.hpp"
#include "earshot/audio/spectral_kernels.hpp"

namespace earshot::audio {
namespace {

/// One partition's values as round(v / scale), scale = largest |v| / 32767.
void quantise(const std::vector<float>& values, float& scale, std::int16_t* out) {
  float peak = 0.0f;
  for (float v : values) peak = std::max(peak, std::abs(v));
  scale = peak > 0.0f ? peak / 32767.0f : 1.0f;
  for (std::size_t i = 0; i < values.size(); ++i)
    out[i] = static_cast<std::int16_t>(std::clamp(std::lround(values[i] / scale), -32767L, 32767L));
}

}  // namespace

HrtfSpectra::HrtfSpectra(const hrtf::HrtfSet& set, std::size_t block)
    : block_(block),
      parts_(std::max<std::size_t>(1, block ? (set.filter_length() + block - 1) / block : 1)),
      measurements_(set.all_measurement_count()) {
  if (block == 0) throw std::invalid_argument("HrtfSpectra: block must be > 0");
  const std::size_t P = 2 * stride(), M = set.all_measurement_count();
  head_.assign(M * 2 * P, 0.0f);
  tail_.assign(M * 2 * (parts_ - 1) * P, 0);
  scale_.assign(M * 2 * (parts_ - 1), 0.0f);
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
          quantise(planar, scale_[lane * (parts_ - 1) + p - 1], tail_.data() + (lane * (parts_ - 1) + p - 1) * P);
      }
    }
}

HrtfSpectra::HrtfSpectra(const hrtf::HrtfSet& set, Stored s)
    : block_(s.block),
      parts_(std::max<std::size_t>(1, s.block ? (set.filter_length() + s.block - 1) / s.block : 1)),
      measurements_(set.all_measurement_count()) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("stored HRTF spectra: " + what); };
  if (block_ == 0 || block_ > kMaxStoredBlock) fail("block " + std::to_string(block_));
  const std::size_t P = 2 * stride(), M = measurements_;
  if (s.head.size() != M * 2 * P || s.tail.size() != M * 2 * (parts_ - 1) * P || s.scale.size() != M * 2 * (parts_ - 1))
    fail("sizes do not fit " + std::to_string(M) + " measurements, block " + std::to_string(block_) + " and " +
         std::to_string(parts_) + " partitions");
  for (const float v : s.head)
    if (!std::isfinite(v)) fail("a head value is not finite");
  for (const float v : s.scale)
    if (!std::isfinite(v)) fail("a tail scale is not finite");
  head_ = std::move(s.head);
  tail_ = std::move(s.tail);
  scale_ = std::move(s.scale);
}

HrtfSpectra::Stored HrtfSpectra::stored() const {
  return {block_, head_, tail_, scale_};
}

std::span<const float> HrtfSpectra::head(std::size_t m, hrtf::Ear ear) const {
  const std::size_t P = 2 * stride();
  return {head_.data() + (2 * m + static_cast<std::size_t>(ear)) * P, P};
}

std::span<const std::int16_t> HrtfSpectra::tail(std::size_t m, hrtf::Ear ear) const {
  const std::size_t n = (parts_ - 1) * 2 * stride();
  return {tail_.data() + (2 * m + static_cast<std::size_t>(ear)) * n, n};
}

std::span<const float> HrtfSpectra::tail_scale(std::size_t m, hrtf::Ear ear) const {
  return {scale_.data() + (2 * m + static_cast<std::size_t>(ear)) * (parts_ - 1), parts_ - 1};
}

}  // namespace earshot::audio
