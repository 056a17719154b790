#include "earshot/audio/binaural_convolver.hpp"

#include <algorithm>
#include <stdexcept>

namespace earshot::audio {

BinauralConvolver::BinauralConvolver(std::size_t block, std::size_t max_filter_length)
    : block_(block),
      parts_(std::max<std::size_t>(1, (max_filter_length + block - 1) / block)),
      bins_(block + 1),
      fft_(2 * block),
      input_(2 * block, 0.0f),
      history_(parts_ * bins_),
      acc_(bins_),
      time_(2 * block),
      old_out_(block),
      padded_(2 * block) {
  if (block == 0) throw std::invalid_argument("BinauralConvolver: block must be > 0");
  for (auto& bank : filters_)
    for (auto& ear : bank) ear.assign(parts_ * bins_, {0.0f, 0.0f});
}

void BinauralConvolver::reset() {
  std::fill(input_.begin(), input_.end(), 0.0f);
  std::fill(history_.begin(), history_.end(), std::complex<float>{});
}

void BinauralConvolver::transform_filter(std::span<const float> ir, std::span<std::complex<float>> bank) {
  // Partition p holds taps [pB, pB + B) zero-padded to 2B.
  for (std::size_t p = 0; p < parts_; ++p) {
    std::fill(padded_.begin(), padded_.end(), 0.0f);
    const std::size_t from = p * block_;
    if (from < ir.size()) {
      const std::size_t n = std::min(block_, ir.size() - from);
      std::copy_n(ir.begin() + static_cast<std::ptrdiff_t>(from), n, padded_.begin());
    }
    fft_.forward(padded_, bank.subspan(p * bins_, bins_));
  }
}

void BinauralConvolver::set_filters(std::span<const float> left, std::span<const float> right) {
  if (left.size() > parts_ * block_ || right.size() > parts_ * block_)
    throw std::invalid_argument("BinauralConvolver: filter longer than max_filter_length");
  const auto banks = begin_filter_update();
  transform_filter(left, banks[0]);
  transform_filter(right, banks[1]);
  end_filter_update();
}

std::array<std::span<std::complex<float>>, 2> BinauralConvolver::begin_filter_update() {
  // The first filters take effect at once; later ones go to the other bank
  // and are crossfaded in during the next process().
  const int target = have_filters_ ? 1 - current_ : current_;
  return {std::span(filters_[target][0]), std::span(filters_[target][1])};
}

void BinauralConvolver::end_filter_update() {
  pending_ = have_filters_;
  have_filters_ = true;
}

void BinauralConvolver::convolve(const Spectrum& bank, std::span<float> out) {
  std::fill(acc_.begin(), acc_.end(), std::complex<float>{});
  for (std::size_t p = 0; p < parts_; ++p) {
    // Partition p meets the input spectrum of p blocks ago.
    const std::size_t h = (head_ + parts_ - p) % parts_;
    // std::complex's operator* guards against NaN and infinity and so does
    // not vectorise; the plain formula on interleaved floats does.
    const float* x = reinterpret_cast<const float*>(history_.data() + h * bins_);
    const float* f = reinterpret_cast<const float*>(bank.data() + p * bins_);
    float* a = reinterpret_cast<float*>(acc_.data());
    for (std::size_t k = 0; k < 2 * bins_; k += 2) {
      a[k] += x[k] * f[k] - x[k + 1] * f[k + 1];
      a[k + 1] += x[k] * f[k + 1] + x[k + 1] * f[k];
    }
  }
  fft_.inverse(acc_, time_);
  std::copy_n(time_.begin() + static_cast<std::ptrdiff_t>(block_), block_, out.begin());  // overlap-save: keep the last B
}

void BinauralConvolver::process(std::span<const float> in, std::span<float> left, std::span<float> right) {
  std::copy_n(input_.begin() + static_cast<std::ptrdiff_t>(block_), block_, input_.begin());
  std::copy_n(in.begin(), block_, input_.begin() + static_cast<std::ptrdiff_t>(block_));
  head_ = (head_ + 1) % parts_;
  fft_.forward(input_, std::span(history_).subspan(head_ * bins_, bins_));

  const int cur = current_;
  convolve(filters_[cur][0], left);
  convolve(filters_[cur][1], right);
  if (!pending_) return;
  // Crossfade from the old filters (just computed) to the new ones.
  const int next = 1 - cur;
  const float step = 1.0f / static_cast<float>(block_);
  for (int ear = 0; ear < 2; ++ear) {
    std::span<float> out = ear == 0 ? left : right;
    std::copy_n(out.begin(), block_, old_out_.begin());
    convolve(filters_[next][ear], out);
    for (std::size_t i = 0; i < block_; ++i) {
      const float w = (static_cast<float>(i) + 1.0f) * step;
      out[i] = (1.0f - w) * old_out_[i] + w * out[i];
    }
  }
  current_ = next;
  pending_ = false;
}

}  // namespace earshot::audio
