#include "earshot/audio/near_field.hpp"

#include "earshot/audio/real_fft.hpp"
#include "earshot/audio/spectral_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>
#include <tuple>

namespace earshot::audio {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kFft = 512;    // design grid: the FIR's magnitude is sampled on kFft / 2 + 1 bins
constexpr std::size_t kFade = 16;    // taps faded out at the FIR's end (half a Hann window)
constexpr double kAngleStep = kPi / static_cast<double>(NearFieldTable::kAngles - 1);

/// The minimum-phase FIR (first `out.size()` taps, end faded) with the
/// magnitude whose natural logarithm is `log_mag` on bins 0..kFft/2: the
/// real cepstrum folded onto positive quefrencies, exponentiated. `fft` is a
/// kFft-point real FFT and `spectrum` / `time` its scratch (design time only,
/// float: the taps are float and the log magnitudes span a few nepers).
void minimum_phase(std::span<const double> log_mag, const RealFft& fft, std::vector<std::complex<float>>& spectrum,
                   std::vector<float>& time, std::span<float> out) {
  for (std::size_t k = 0; k <= kFft / 2; ++k) spectrum[k] = {static_cast<float>(log_mag[k]), 0.0f};
  fft.inverse(spectrum, time);  // the real cepstrum (even, so real)
  for (std::size_t n = 1; n < kFft / 2; ++n) time[n] *= 2.0f;
  std::fill(time.begin() + kFft / 2 + 1, time.end(), 0.0f);
  fft.forward(time, spectrum);
  for (auto& v : spectrum) v = std::exp(v);
  fft.inverse(spectrum, time);
  const std::size_t T = out.size();
  for (std::size_t n = 0; n < T; ++n) {
    double w = 1.0;
    if (n + kFade >= T) w = 0.5 * (1.0 + std::cos(kPi * static_cast<double>(n + kFade + 1 - T) / (kFade + 1)));
    out[n] = static_cast<float>(static_cast<double>(time[n]) * w);
  }
}

/// A series' coefficients split into real and imaginary parts, so that
/// summing it against stored Legendre values is two plain dot products.
struct PlanarSeries {
  std::vector<double> re, im;
  explicit PlanarSeries(const hrtf::RigidSphereSeries& s) {
    // The series converges past m ~ mu and |P_m| <= 1, so the terms after
    // the last coefficient above 1e-10 of the largest change the sum by far
    // less than a float tap resolves (near the head they are half the terms).
    const auto& c = s.coefficients();
    double largest = 0.0;
    for (const auto& v : c) largest = std::max(largest, std::abs(v));
    std::size_t n = c.size();
    while (n > 1 && std::abs(c[n - 1]) < 1e-10 * largest) --n;
    for (std::size_t m = 0; m < n; ++m) {
      re.push_back(c[m].real());
      im.push_back(c[m].imag());
    }
  }
  /// |sum_m c_m p[m]|^2; `p` holds at least as many Legendre values as terms.
  [[nodiscard]] double power(const double* p) const {
    // Four partial sums: the loop pipelines (and vectorises) without
    // reassociation flags; the order differs from a single sum by rounding only.
    double r[4] = {0, 0, 0, 0}, i[4] = {0, 0, 0, 0};
    const std::size_t n = re.size(), n4 = n & ~std::size_t{3};
    for (std::size_t m = 0; m < n4; m += 4)
      for (std::size_t j = 0; j < 4; ++j) {
        r[j] += re[m + j] * p[m + j];
        i[j] += im[m + j] * p[m + j];
      }
    for (std::size_t m = n4; m < n; ++m) {
      r[0] += re[m] * p[m];
      i[0] += im[m] * p[m];
    }
    const double re_sum = (r[0] + r[1]) + (r[2] + r[3]), im_sum = (i[0] + i[1]) + (i[2] + i[3]);
    return re_sum * re_sum + im_sum * im_sum;
  }
};

/// P_0 .. P_{out.size() - 1} at cos(theta), by the upward recurrence.
void legendre(double theta, std::span<double> out) {
  const double x = std::cos(theta);
  double p_prev = 0.0, p = 1.0;
  for (std::size_t m = 0; m < out.size(); ++m) {
    out[m] = p;
    const double md = static_cast<double>(m);
    const double next = ((2.0 * md + 1.0) * x * p - md * p_prev) / (md + 1.0);
    p_prev = p;
    p = next;
  }
}

/// The angle (0..pi) from the ear's axis at which the ray from the ear at
/// distance a through a source at (r, theta) meets the circle of radius R.
double parallax_angle(double a, double r, double theta, double R) {
  const double sx = r * std::cos(theta), sy = r * std::sin(theta);
  const double dx = sx - a, dy = sy;
  const double dd = dx * dx + dy * dy;
  if (dd < 1e-18) return 0.0;
  const double ed = a * dx;
  const double t = (-ed + std::sqrt(std::max(0.0, ed * ed - dd * (a * a - R * R)))) / dd;
  return std::atan2(std::abs(t * dy), a + t * dx);
}

}  // namespace

Vec3 parallax_direction(const Vec3& s, double ear_y, double R) {
  const Vec3 d{s[0], s[1] - ear_y, s[2]};
  const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  if (dd < 1e-18) return {0.0, ear_y >= 0.0 ? 1.0 : -1.0, 0.0};
  const double ed = ear_y * d[1];
  const double t = (-ed + std::sqrt(std::max(0.0, ed * ed - dd * (ear_y * ear_y - R * R)))) / dd;
  const Vec3 p{t * d[0], ear_y + t * d[1], t * d[2]};
  const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  return {p[0] / n, p[1] / n, p[2] / n};
}

NearFieldTable::NearFieldTable(double sample_rate, std::span<const double> shells_m, hrtf::SphereHead head)
    : rate_(sample_rate), head_(head), r_min_(1.15 * head.radius_m), shells_(shells_m.begin(), shells_m.end()) {
  if (shells_.empty()) throw std::invalid_argument("NearFieldTable: no measurement distance");
  if (!(sample_rate > 0.0)) throw std::invalid_argument("NearFieldTable: sample rate must be > 0");
  const double far = shells_.front();
  if (!(far > r_min_)) return;  // nothing is nearer than the set: no table
  inv_near_ = 1.0 / r_min_;
  inv_far_ = 1.0 / far;
  taps_.assign(shells_.size() * kDistances * kAngles * kTaps, 0.0f);
  // The model is smooth in frequency: evaluated at 0 Hz and kEval
  // frequencies spaced evenly in log f up to Nyquist, its log magnitude is
  // interpolated (linearly in log f) onto the design bins. One series per
  // distance and frequency serves every angle.
  constexpr std::size_t kEval = 72;
  constexpr double kLowest = 40.0;
  std::vector<double> freqs{0.0};
  for (std::size_t k = 0; k < kEval; ++k)
    freqs.push_back(kLowest * std::pow(0.5 * rate_ / kLowest, static_cast<double>(k) / (kEval - 1)));
  std::vector<double> log_ratio(freqs.size());  // one grid point's, by frequency
  std::vector<double> log_mag(kFft / 2 + 1);
  // Design bin b lies between evaluated frequencies bin_from[b] and the next,
  // a fraction bin_t[b] of the way (linear in f below the lowest, else in log f).
  std::vector<std::size_t> bin_from(kFft / 2 + 1);
  std::vector<double> bin_t(kFft / 2 + 1);
  for (std::size_t b = 0, k = 1; b <= kFft / 2; ++b) {
    const double f = static_cast<double>(b) * rate_ / kFft;
    while (k + 1 < freqs.size() && freqs[k] < f) ++k;  // freqs[k - 1] < f <= freqs[k]
    bin_from[b] = k - 1;
    bin_t[b] = k == 1 ? std::min(1.0, f / freqs[1])
                      : std::clamp(std::log(f / freqs[k - 1]) / std::log(freqs[k] / freqs[k - 1]), 0.0, 1.0);
  }
  std::vector<double> radii(kDistances);
  for (std::size_t d = 0; d < kDistances; ++d)
    radii[d] = 1.0 / (inv_near_ + (inv_far_ - inv_near_) * static_cast<double>(d) / (kDistances - 1));
  // The sources' series (every distance and frequency) serve every shell;
  // the Legendre values at the grid's angles serve every series. Near the
  // head a series needs a few hundred terms, so this is where the time goes.
  std::vector<PlanarSeries> at_source;  // [distance][frequency]
  std::size_t terms = 0;
  for (std::size_t d = 0; d < kDistances; ++d)
    for (const double f : freqs) {
      at_source.emplace_back(hrtf::RigidSphereSeries(radii[d], f, head));
      terms = std::max(terms, at_source.back().re.size());
    }
  std::vector<double> p_source(kAngles * terms);  // [angle][m]
  for (std::size_t a = 0; a < kAngles; ++a)
    legendre(static_cast<double>(a) * kAngleStep, std::span<double>(p_source.data() + a * terms, terms));
  std::vector<double> p_shell;
  const RealFft fft(kFft);
  std::vector<std::complex<float>> spectrum(kFft / 2 + 1);
  std::vector<float> time(kFft);
  for (std::size_t s = 0; s < shells_.size(); ++s) {
    const double R = std::max(shells_[s], r_min_);
    std::vector<PlanarSeries> at_shell;  // [frequency]
    std::size_t shell_terms = 0;
    for (const double f : freqs) {
      at_shell.emplace_back(hrtf::RigidSphereSeries(R, f, head));
      shell_terms = std::max(shell_terms, at_shell.back().re.size());
    }
    p_shell.resize(shell_terms);
    for (std::size_t d = 0; d < kDistances; ++d)
      for (std::size_t a = 0; a < kAngles; ++a) {
        // The shell's response is read where the ear's ray meets it.
        legendre(parallax_angle(head.radius_m, radii[d], static_cast<double>(a) * kAngleStep, R), p_shell);
        double* lr = log_ratio.data();
        for (std::size_t k = 0; k < freqs.size(); ++k) {
          const double num = at_source[d * freqs.size() + k].power(p_source.data() + a * terms);
          const double den = at_shell[k].power(p_shell.data());
          lr[k] = 0.5 * std::log(std::max(num, 1e-12) / std::max(den, 1e-12));
        }
        for (std::size_t b = 0; b <= kFft / 2; ++b)
          log_mag[b] = lr[bin_from[b]] + (lr[bin_from[b] + 1] - lr[bin_from[b]]) * bin_t[b];
        minimum_phase(log_mag, fft, spectrum, time,
                      std::span<float>(taps_.data() + ((s * kDistances + d) * kAngles + a) * kTaps, kTaps));
      }
  }
}

std::shared_ptr<const NearFieldTable> NearFieldTable::shared(double sample_rate, std::span<const double> shells_m,
                                                             hrtf::SphereHead head) {
  using Key = std::tuple<double, std::vector<double>, double, double>;
  static std::mutex mutex;
  static std::map<Key, std::shared_ptr<const NearFieldTable>> tables;
  const Key key{sample_rate, std::vector<double>(shells_m.begin(), shells_m.end()), head.radius_m, head.speed_of_sound};
  const std::lock_guard lock(mutex);
  auto& t = tables[key];
  if (!t) t = std::make_shared<const NearFieldTable>(sample_rate, shells_m, head);
  return t;
}

bool NearFieldTable::taps(std::size_t shell, double r, double theta, std::span<float> out) const {
  const GridPoint g = locate(shell, r, theta);
  if (!g.on || out.size() < kTaps) return false;
  taps_at(g, out);
  return true;
}

NearFieldTable::GridPoint NearFieldTable::locate(std::size_t shell, double r, double theta) const {
  GridPoint g;
  g.shell = shell;
  if (taps_.empty() || shell >= shells_.size()) return g;
  if (shell == 0 && r >= shells_.front()) return g;
  const double u = 1.0 / std::clamp(r, r_min_, shells_.front());
  g.distance = std::clamp((inv_near_ - u) / (inv_near_ - inv_far_), 0.0, 1.0) * (kDistances - 1);
  g.angle = std::clamp(std::abs(theta), 0.0, kPi) / kAngleStep;
  g.on = true;
  return g;
}

void NearFieldTable::taps_at(const GridPoint& g, std::span<float> out) const {
  if (!g.on || g.shell >= shells_.size() || out.size() < kTaps) return;
  const auto d0 = std::min(static_cast<std::size_t>(g.distance), kDistances - 2);
  const auto a0 = std::min(static_cast<std::size_t>(g.angle), kAngles - 2);
  const auto fd = static_cast<float>(g.distance - static_cast<double>(d0)),
             fa = static_cast<float>(g.angle - static_cast<double>(a0));
  const float w00 = (1 - fd) * (1 - fa), w01 = (1 - fd) * fa, w10 = fd * (1 - fa), w11 = fd * fa;
  const float *h00 = fir(g.shell, d0, a0), *h01 = fir(g.shell, d0, a0 + 1), *h10 = fir(g.shell, d0 + 1, a0),
              *h11 = fir(g.shell, d0 + 1, a0 + 1);
  for (std::size_t k = 0; k < kTaps; ++k) out[k] = w00 * h00[k] + w01 * h01[k] + w10 * h10[k] + w11 * h11[k];
}

NearFieldFilter::NearFieldFilter(std::size_t block) : block_(block) {
  line_.assign(NearFieldTable::kTaps - 1 + block, 0.0f);
  from_[0] = 1.0f;
}

void NearFieldFilter::reset() {
  std::fill(line_.begin(), line_.end(), 0.0f);
  from_.fill(0.0f);
  from_[0] = 1.0f;
  from_unity_ = true;
}

void NearFieldFilter::process(std::span<float> x, std::span<const float> taps) {
  constexpr std::size_t T = NearFieldTable::kTaps;
  const std::size_t B = std::min(block_, x.size());
  std::copy_n(x.data(), B, line_.data() + T - 1);
  const bool to_unity = taps.size() < T;
  if (to_unity) {
    to_.fill(0.0f);
    to_[0] = 1.0f;
  } else {
    std::copy_n(taps.data(), T, to_.data());
  }
  if (!(from_unity_ && to_unity)) {
    // One pass gives both ends' outputs and the glide between them (the
    // same taps at both ends when the source did not move).
    const bool same = std::memcmp(from_.data(), to_.data(), sizeof(float) * T) == 0;
    kernels::fir_glide(from_.data(), same ? from_.data() : to_.data(), T, line_.data() + T - 1, x.data(), B);
  }
  std::copy_n(line_.data() + B, T - 1, line_.data());
  from_ = to_;
  from_unity_ = to_unity;
}

}  // namespace earshot::audio
