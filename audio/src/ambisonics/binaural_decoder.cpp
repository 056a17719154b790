#include "earshot/audio/ambisonics/binaural_decoder.hpp"

#include <algorithm>
#include <stdexcept>

#include "earshot/audio/hrtf_spectra.hpp"
#include "earshot/audio/spectral_kernels.hpp"

namespace earshot::ambisonics {

BinauralDecoder::BinauralDecoder(const DecoderFilters& filters, std::size_t block)
    : order_(filters.order),
      channels_(filters.channels()),
      block_(block),
      parts_(block ? std::max<std::size_t>(1, (filters.length + block - 1) / block) : 1),
      stride_(audio::partition_stride(block)),
      fft_(2 * std::max<std::size_t>(block, 1)) {
  if (block == 0) throw std::invalid_argument("BinauralDecoder: block must be > 0");
  if (filters.taps.size() != 2 * channels_ * filters.length)
    throw std::invalid_argument("BinauralDecoder: filters hold " + std::to_string(filters.taps.size()) + " taps, not " +
                                std::to_string(2 * channels_ * filters.length));
  const std::size_t B = block, P = 2 * stride_;
  filters_.assign(2 * channels_ * parts_ * P, 0.0f);
  history_.assign(channels_ * parts_ * P, 0.0f);
  window_.assign(channels_ * 2 * B, 0.0f);
  acc_.assign(P, 0.0f);
  spectrum_.assign(B + 1, {});
  time_.assign(2 * B, 0.0f);
  audio::AlignedVector<float> padded(2 * B);
  for (std::size_t e = 0; e < 2; ++e)
    for (std::size_t c = 0; c < channels_; ++c) {
      const auto h = filters.filter(e, c);
      for (std::size_t p = 0; p < parts_; ++p) {
        std::fill(padded.begin(), padded.end(), 0.0f);
        const std::size_t from = p * B;
        if (from < h.size()) std::copy_n(h.begin() + static_cast<long>(from), std::min(B, h.size() - from), padded.begin());
        fft_.forward(padded, spectrum_);
        audio::kernels::to_planar(spectrum_.data(), B + 1, filters_.data() + ((e * channels_ + c) * parts_ + p) * P, stride_);
      }
    }
}

void BinauralDecoder::reset() {
  std::fill(history_.begin(), history_.end(), 0.0f);
  std::fill(window_.begin(), window_.end(), 0.0f);
  now_ = 0;
}

void BinauralDecoder::process(std::span<const float> in, std::span<float> left, std::span<float> right) {
  const std::size_t B = block_, P = 2 * stride_;
  if (in.size() < channels_ * B || left.size() < B || right.size() < B) return;
  // Each channel's window [previous block | this block] into its history slot.
  for (std::size_t c = 0; c < channels_; ++c) {
    float* w = window_.data() + c * 2 * B;
    std::copy_n(w + B, B, w);
    std::copy_n(in.data() + c * B, B, w + B);
    fft_.forward_planar(std::span<const float>(w, 2 * B), history_.data() + (c * parts_ + now_) * P, stride_, false);
  }
  for (std::size_t e = 0; e < 2; ++e) {
    std::fill(acc_.begin(), acc_.end(), 0.0f);
    for (std::size_t c = 0; c < channels_; ++c) {
      const float* h = filters_.data() + (e * channels_ + c) * parts_ * P;
      const float* x = history_.data() + c * parts_ * P;
      // Partition p meets the input of p blocks ago.
      for (std::size_t p = 0, slot = now_; p < parts_; ++p) {
        audio::kernels::multiply_add(x + slot * P, h + p * P, acc_.data(), stride_);
        slot = slot == 0 ? parts_ - 1 : slot - 1;
      }
    }
    audio::kernels::to_interleaved(acc_.data(), stride_, spectrum_.data(), B + 1);
    fft_.inverse_destroying(std::span(spectrum_).first(B + 1), time_);
    std::span<float> out = e == 0 ? left : right;
    std::copy_n(time_.data() + B, B, out.begin());
  }
  now_ = now_ + 1 == parts_ ? 0 : now_ + 1;
}

}  // namespace earshot::ambisonics
