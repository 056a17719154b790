#include "earshot/audio/reverb_fdn.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "earshot/audio/decay_filter.hpp"
#include "prime_lengths.hpp"

namespace earshot::audio {
namespace {

constexpr std::size_t N = ReverbFdn::kLines;
// Line lengths at density 1 (ms): roughly geometric from 11 to 37 ms, so that
// echo times do not pile up; each is rounded to a prime number of samples.
constexpr std::array<double, N> kLineMs{11.0, 11.9, 12.9, 14.0, 15.1, 16.4, 17.7, 19.2,
                                        20.8, 22.5, 24.4, 26.4, 28.6, 31.0, 33.6, 36.9};
constexpr std::array<double, ReverbFdn::kDiffusers> kDiffuserMs{1.13, 1.71, 2.63, 3.89};
constexpr double kMaxSpread = 1.0;

// Sign of the Sylvester-Hadamard matrix, row r, column c.
constexpr float hadamard(std::size_t r, std::size_t c) { return std::popcount(r & c) % 2 ? -1.0f : 1.0f; }
constexpr std::size_t kRowIn = 7, kRowLeft = 5, kRowRight = 10;

using detail::prime_at_least;

// In-place fast Walsh-Hadamard transform of 16 values, scaled to be orthogonal.
inline void hadamard16(std::array<float, N>& v) {
  for (std::size_t h = 1; h < N; h *= 2)
    for (std::size_t i = 0; i < N; i += 2 * h)
      for (std::size_t j = i; j < i + h; ++j) {
        const float a = v[j], b = v[j + h];
        v[j] = a + b;
        v[j + h] = a - b;
      }
  for (auto& x : v) x *= 0.25f;  // 1 / sqrt(16)
}

}  // namespace

ReverbFdn::ReverbFdn(double sample_rate, std::size_t /*block*/) : rate_(sample_rate) {
  const auto longest = static_cast<std::size_t>(std::ceil(kLineMs.back() * kMaxSpread * 1e-3 * sample_rate)) + 64;
  stride_ = std::bit_ceil(longest);
  mask_ = stride_ - 1;
  lines_.assign(N * stride_, 0.0f);
  const auto longest_diff = static_cast<std::size_t>(std::ceil(kDiffuserMs.back() * 1e-3 * sample_rate)) + 2;
  diff_stride_ = std::bit_ceil(longest_diff);
  diff_mask_ = diff_stride_ - 1;
  diff_buf_.assign(kDiffusers * diff_stride_, 0.0f);
  for (std::size_t k = 0; k < kDiffusers; ++k)
    diff_len_[k] = prime_at_least(static_cast<std::size_t>(std::lround(kDiffuserMs[k] * 1e-3 * sample_rate)));
  update(RoomParams{});
}

void ReverbFdn::reset() {
  std::fill(lines_.begin(), lines_.end(), 0.0f);
  std::fill(diff_buf_.begin(), diff_buf_.end(), 0.0f);
  for (std::size_t s = 0; s < 2; ++s) z1_[s].fill(0.0f), z2_[s].fill(0.0f);
}

double ReverbFdn::latency_s() const { return static_cast<double>(length_[0]) / rate_; }

void ReverbFdn::update(const RoomParams& p) {
  const double spread = 0.4 + 0.6 * std::clamp(p.density, 0.0, 1.0);
  const double t60 = std::clamp(p.decay_time_s, 0.05, 100.0);
  const double ratio = std::clamp(p.decay_hf_ratio, 0.05, 4.0);
  const double f_hf = std::min(p.hf_reference_hz, 0.45 * rate_);
  double mean_g2 = 0.0;
  for (std::size_t i = 0; i < N; ++i) {
    length_[i] = std::min(prime_at_least(static_cast<std::size_t>(std::lround(kLineMs[i] * spread * 1e-3 * rate_))),
                          stride_ - 1);
    const double m = static_cast<double>(length_[i]);
    // dB lost per pass: 60 dB per t60 at mid, per t60 * ratio at f_hf.
    const DecayFilter d = design_decay_filter(m, t60, ratio, f_hf, rate_);
    const auto& shelf = d.shelf;
    gain_[i] = static_cast<float>(d.gain);
    mean_g2 += d.gain * d.gain / N;
    for (std::size_t s = 0; s < 2; ++s) {
      b0_[s][i] = static_cast<float>(shelf[s].b0);
      b1_[s][i] = static_cast<float>(shelf[s].b1);
      b2_[s][i] = static_cast<float>(shelf[s].b2);
      a1_[s][i] = static_cast<float>(shelf[s].a1);
      a2_[s][i] = static_cast<float>(shelf[s].a2);
    }
  }
  // Diffusion 0 still diffuses a little: the lines alone would take ~120 ms to
  // build a dense tail.
  diff_g_ = static_cast<float>(0.35 + 0.35 * std::clamp(p.diffusion, 0.0, 1.0));
  // Energy out / energy in ~ g^2 / (N (1 - g^2)) for uncorrelated lines and
  // unit-norm input and output vectors: undo that, then apply the level.
  const double level = std::clamp(p.late_reverb_gain, 0.0, 10.0);
  out_gain_ = static_cast<float>(level * std::sqrt(N * (1.0 - mean_g2) / mean_g2) / std::sqrt(double(N)));
}

void ReverbFdn::process(std::span<const float> in, std::span<float> out_left, std::span<float> out_right) {
  const float in_norm = 0.25f;  // b: Hadamard row kRowIn / sqrt(16)
  std::array<float, N> y;
  for (std::size_t n = 0; n < in.size(); ++n) {
    // Diffusion: Schroeder allpasses in series.
    float x = in[n];
    for (std::size_t k = 0; k < kDiffusers; ++k) {
      float* buf = diff_buf_.data() + k * diff_stride_;
      const float d = buf[(write_ - diff_len_[k]) & diff_mask_];
      const float v = x + diff_g_ * d;
      buf[write_ & diff_mask_] = v;
      x = d - diff_g_ * v;
    }
    for (std::size_t i = 0; i < N; ++i) y[i] = lines_[i * stride_ + ((write_ - length_[i]) & mask_)];
    // Absorption: gain, then the two shelf sections (transposed direct form II).
    for (std::size_t i = 0; i < N; ++i) y[i] *= gain_[i];
    for (std::size_t s = 0; s < 2; ++s)
      for (std::size_t i = 0; i < N; ++i) {
        const float u = y[i];
        const float v = b0_[s][i] * u + z1_[s][i];
        z1_[s][i] = b1_[s][i] * u - a1_[s][i] * v + z2_[s][i];
        z2_[s][i] = b2_[s][i] * u - a2_[s][i] * v;
        y[i] = v;
      }
    float l = 0.0f, r = 0.0f;
    for (std::size_t i = 0; i < N; ++i) {
      l += hadamard(kRowLeft, i) * y[i];
      r += hadamard(kRowRight, i) * y[i];
    }
    out_left[n] = l * out_gain_;
    out_right[n] = r * out_gain_;
    hadamard16(y);
    const std::size_t w = write_ & mask_;
    for (std::size_t i = 0; i < N; ++i) lines_[i * stride_ + w] = y[i] + in_norm * hadamard(kRowIn, i) * x;
    ++write_;
  }
}

}  // namespace earshot::audio
