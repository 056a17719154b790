#include "earshot/audio/reverb_schroeder.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "earshot/audio/decay_filter.hpp"
#include "prime_lengths.hpp"

namespace earshot::audio {
namespace {

constexpr std::array<double, ReverbSchroeder::kCombs> kCombMs{24.7, 26.3, 28.1, 29.9, 31.6, 33.2, 35.1, 36.9};
// Left ear, then right ear; Schroeder's 5 ms and 1.7 ms among them.
constexpr std::array<double, 2 * ReverbSchroeder::kAllpasses> kAllpassMs{5.0, 3.1, 1.7, 0.71,
                                                                         5.4, 3.5, 1.9, 0.83};

using detail::prime_at_least;

}  // namespace

ReverbSchroeder::ReverbSchroeder(double sample_rate, std::size_t /*block*/) : rate_(sample_rate) {
  comb_stride_ = std::bit_ceil(static_cast<std::size_t>(std::ceil(kCombMs.back() * 1e-3 * sample_rate)) + 64);
  comb_mask_ = comb_stride_ - 1;
  combs_.assign(kCombs * comb_stride_, 0.0f);
  ap_stride_ = std::bit_ceil(static_cast<std::size_t>(std::ceil(5.4e-3 * sample_rate)) + 64);
  ap_mask_ = ap_stride_ - 1;
  allpass_.assign(2 * kAllpasses * ap_stride_, 0.0f);
  for (std::size_t k = 0; k < ap_len_.size(); ++k)
    ap_len_[k] = prime_at_least(static_cast<std::size_t>(std::lround(kAllpassMs[k] * 1e-3 * sample_rate)));
  update(RoomParams{});
}

void ReverbSchroeder::reset() {
  std::fill(combs_.begin(), combs_.end(), 0.0f);
  std::fill(allpass_.begin(), allpass_.end(), 0.0f);
  for (std::size_t s = 0; s < 2; ++s) z1_[s].fill(0.0f), z2_[s].fill(0.0f);
}

double ReverbSchroeder::latency_s() const { return static_cast<double>(comb_len_[0]) / rate_; }

void ReverbSchroeder::update(const RoomParams& p) {
  const double spread = 0.4 + 0.6 * std::clamp(p.density, 0.0, 1.0);
  const double t60 = std::clamp(p.decay_time_s, 0.05, 100.0);
  const double ratio = std::clamp(p.decay_hf_ratio, 0.05, 4.0);
  const double f_hf = std::min(p.hf_reference_hz, 0.45 * rate_);
  double mean_gain = 0.0;  // energy gain of a comb from its input to its output
  for (std::size_t i = 0; i < kCombs; ++i) {
    comb_len_[i] = std::min(prime_at_least(static_cast<std::size_t>(std::lround(kCombMs[i] * spread * 1e-3 * rate_))),
                            comb_stride_ - 1);
    const double m = static_cast<double>(comb_len_[i]);
    const DecayFilter d = design_decay_filter(m, t60, ratio, f_hf, rate_);
    const double g = d.gain;
    feedback_[i] = static_cast<float>(g);
    for (std::size_t s = 0; s < 2; ++s) damp_[s][i] = d.shelf[s];
    mean_gain += 1.0 / (1.0 - g * g) / kCombs;
  }
  ap_g_ = static_cast<float>(0.5 + 0.2 * std::clamp(p.diffusion, 0.0, 1.0));
  // A comb passes its input once unattenuated, then g^2 less energy per
  // round: 1 / (1 - g^2) of the input's energy; the K combs add up (their
  // echoes do not coincide). The allpasses keep the energy.
  const double level = std::clamp(p.late_reverb_gain, 0.0, 10.0);
  out_gain_ = static_cast<float>(level / std::sqrt(kCombs * mean_gain));
}

void ReverbSchroeder::process(std::span<const float> in, std::span<float> out_left, std::span<float> out_right) {
  for (std::size_t n = 0; n < in.size(); ++n) {
    const float x = in[n];
    float left = 0.0f, right = 0.0f;
    const std::size_t w = write_ & comb_mask_;
    for (std::size_t i = 0; i < kCombs; ++i) {
      float* ring = combs_.data() + i * comb_stride_;
      const float y = ring[(write_ - comb_len_[i]) & comb_mask_];
      float v = feedback_[i] * y;
      for (std::size_t s = 0; s < 2; ++s) {  // damping shelf, transposed direct form II
        const auto& c = damp_[s][i];
        const float u = v;
        v = c.b0 * u + z1_[s][i];
        z1_[s][i] = c.b1 * u - c.a1 * v + z2_[s][i];
        z2_[s][i] = c.b2 * u - c.a2 * v;
      }
      ring[w] = x + v;
      // Orthogonal sign patterns (two rows of an 8 x 8 Hadamard matrix) per ear.
      left += (std::popcount(i & 3u) % 2 ? -y : y);
      right += (std::popcount(i & 5u) % 2 ? -y : y);
    }
    float ear[2] = {left * out_gain_, right * out_gain_};
    for (std::size_t e = 0; e < 2; ++e)
      for (std::size_t k = 0; k < kAllpasses; ++k) {
        float* ring = allpass_.data() + (e * kAllpasses + k) * ap_stride_;
        const float d = ring[(write_ - ap_len_[e * kAllpasses + k]) & ap_mask_];
        const float v = ear[e] + ap_g_ * d;
        ring[write_ & ap_mask_] = v;
        ear[e] = d - ap_g_ * v;
      }
    out_left[n] = ear[0];
    out_right[n] = ear[1];
    ++write_;
  }
}

}  // namespace earshot::audio
