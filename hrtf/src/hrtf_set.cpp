#include "earshot/hrtf/hrtf_set.hpp"
#include "earshot/hrtf/ir_resampler.hpp"
#include "dot.hpp"
#include "sofa_precheck.hpp"

#include <mysofa.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "earshot/errors.hpp"
#include "earshot/windowed_sinc.hpp"

namespace earshot::hrtf {
namespace {

struct MysofaFree {
  void operator()(MYSOFA_HRTF* h) const { mysofa_free(h); }
};
using SofaPtr = std::unique_ptr<MYSOFA_HRTF, MysofaFree>;

std::string mysofa_error_text(int err) {
  switch (err) {
    case MYSOFA_INVALID_FORMAT: return "not a valid SOFA file (invalid or truncated HDF5 structure)";
    case MYSOFA_UNSUPPORTED_FORMAT: return "unsupported SOFA format";
    case MYSOFA_NO_MEMORY: return "out of memory while reading";
    case MYSOFA_READ_ERROR: return "read error (file truncated?)";
    case MYSOFA_INVALID_ATTRIBUTES: return "not of the SimpleFreeFieldHRIR convention (invalid attributes)";
    case MYSOFA_INVALID_DIMENSIONS: return "invalid dimensions for SimpleFreeFieldHRIR";
    case MYSOFA_INVALID_DIMENSION_LIST: return "invalid dimension list";
    case MYSOFA_INVALID_COORDINATE_TYPE: return "invalid coordinate type";
    case MYSOFA_ONLY_EMITTER_WITH_ECI_SUPPORTED: return "only emitters with ECI dimensions are supported";
    case MYSOFA_ONLY_DELAYS_WITH_IR_OR_MR_SUPPORTED: return "Data.Delay must have dimensions IR or MR";
    case MYSOFA_ONLY_THE_SAME_SAMPLING_RATE_SUPPORTED: return "all measurements must share one sampling rate";
    case MYSOFA_RECEIVERS_WITH_RCI_SUPPORTED: return "receivers must have RCI dimensions";
    case MYSOFA_RECEIVERS_WITH_CARTESIAN_SUPPORTED: return "receiver positions must be cartesian";
    case MYSOFA_INVALID_RECEIVER_POSITIONS: return "invalid receiver (ear) positions";
    case MYSOFA_ONLY_SOURCES_WITH_MC_SUPPORTED: return "source positions must have MC dimensions";
    default: return "libmysofa error " + std::to_string(err);
  }
}

[[noreturn]] void bad(const std::filesystem::path& p, const std::string& what) {
  throw InputError::at(p.string(), 0, "", what);
}

/// Where |h| first reaches -20 dB of its peak, in fractional samples: the
/// crossing is interpolated linearly between the two samples around it, so
/// neighbouring measurements' onsets (and so their ITDs) are not rounded to
/// whole samples.
double onset_of(std::span<const float> h) {
  float peak = 0.0f;
  for (float v : h) peak = std::max(peak, std::abs(v));
  if (peak <= 0.0f) return 0.0;
  const float level = 0.1f * peak;
  for (std::size_t i = 0; i < h.size(); ++i) {
    const float a = std::abs(h[i]);
    if (a < level) continue;
    if (i == 0) return 0.0;
    const float b = std::abs(h[i - 1]);
    return static_cast<double>(i - 1) + static_cast<double>((level - b) / (a - b));
  }
  return 0.0;
}

/// The first sample from which on the response holds all but 1e-6 of its
/// energy (-60 dB): what comes before is silence (or rounding).
std::size_t first_audible(std::span<const float> h) {
  double total = 0.0;
  for (float v : h) total += double(v) * v;
  double before = 0.0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    before += double(h[i]) * h[i];
    if (before > 1e-6 * total) return i;
  }
  return 0;
}

/// out[i] = h(i + shift): h read `shift` samples later, band-limited (a
/// Kaiser-windowed sinc of 64 taps, unit DC gain; samples beyond h are
/// zero). Load time only.
void shift_earlier(std::span<const float> h, double shift, std::span<float> out) {
  constexpr int kHalf = 32;
  constexpr double kBeta = 8.0;
  const double whole = std::floor(shift), frac = shift - whole;
  static const KaiserSinc kernel(kHalf, kBeta);  // immutable once built
  std::array<double, 2 * kHalf> exact{};  // tap t weighs h[i + whole + t - kHalf + 1]
  double sum = 0.0;
  for (int j = -kHalf + 1; j <= kHalf; ++j) {
    exact[static_cast<std::size_t>(j + kHalf - 1)] =
        frac == 0.0 ? (j == 0 ? 1.0 : 0.0) : kernel(static_cast<double>(j) - frac);
    sum += exact[static_cast<std::size_t>(j + kHalf - 1)];
  }
  std::array<float, 2 * kHalf> taps{};
  for (std::size_t t = 0; t < taps.size(); ++t) taps[t] = static_cast<float>(exact[t] / sum);
  const auto n = static_cast<long>(h.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const long k0 = static_cast<long>(i) + static_cast<long>(whole) - kHalf + 1;  // h index of tap 0
    const long lo = std::max(0L, -k0), hi = std::min(static_cast<long>(taps.size()), n - k0);
    out[i] = hi > lo ? detail::dot(taps.data() + lo, h.data() + (k0 + lo), static_cast<std::size_t>(hi - lo)) : 0.0f;
  }
}

/// The unit vector of a direction (SOFA's frame: x ahead, y left, z up).
Vec3 unit_vector(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

}  // namespace

double head_radius_m(HeadSize s) {
  switch (s) {
    case HeadSize::small: return 0.075;
    case HeadSize::medium: return 0.0875;
    case HeadSize::large: return 0.10;
  }
  return 0.0875;
}

double woodworth_itd(double azimuth, double elevation, double r, double c) {
  // Lateral angle: the angle between the source and the median plane.
  const double lateral = std::asin(std::clamp(std::sin(azimuth) * std::cos(elevation), -1.0, 1.0));
  return r / c * (lateral + std::sin(lateral));
}

std::span<const float> HrtfSet::filter(std::size_t i, Ear ear) const {
  return {filters_.data() + (2 * i + static_cast<std::size_t>(ear)) * length_, length_};
}

std::span<const float> HrtfSet::measured_hrir(std::size_t i, Ear ear) const {
  return {hrirs_.data() + (2 * i + static_cast<std::size_t>(ear)) * hrir_length_, hrir_length_};
}

namespace {

/// The file's size, after the checks that need nothing but its name and the
/// render rate; then its HDF5 signature and the sizes its object headers
/// declare (sofa_precheck.hpp), before libmysofa sees it.
void precheck_file(const std::filesystem::path& path, double sample_rate) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) bad(path, "file not found");
  if (!std::filesystem::is_regular_file(path, ec)) bad(path, "not a regular file");
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec || bytes == 0) bad(path, "empty file");
  if (bytes > HrtfSet::kMaxFileBytes)
    bad(path, "file of " + std::to_string(bytes) + " bytes, more than the " + std::to_string(HrtfSet::kMaxFileBytes) +
                  " a SOFA set is read from");
  if (!(sample_rate >= 8000.0 && sample_rate <= 192000.0))
    bad(path, "unsupported render rate " + std::to_string(sample_rate) + " Hz (8000-192000)");
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> file(static_cast<std::size_t>(bytes));
  in.read(reinterpret_cast<char*>(file.data()), static_cast<std::streamsize>(file.size()));
  static constexpr std::array<std::uint8_t, 8> kHdf5{0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
  if (!in || file.size() < kHdf5.size() || !std::equal(kHdf5.begin(), kHdf5.end(), file.begin()))
    bad(path, "not a SOFA file (no HDF5 signature)");
  if (const std::string p = detail::sofa_header_problem(file, HrtfSet::kMaxSamples); !p.empty()) bad(path, p);
}

/// The convention and the dimensions, before anything that grows with them
/// (mysofa_check included: it walks the arrays).
void check_dimensions(const std::filesystem::path& path, MYSOFA_HRTF* h) {
  char conv_name[] = "SOFAConventions";
  const char* conv = mysofa_getAttribute(h->attributes, conv_name);
  if (!conv || std::strcmp(conv, "SimpleFreeFieldHRIR") != 0)
    bad(path, std::string("SOFA convention is '") + (conv ? conv : "(none)") +
                  "', expected 'SimpleFreeFieldHRIR'");
  if (h->R != 2) bad(path, "dimension R (receivers) is " + std::to_string(h->R) + ", expected 2 (two ears)");
  if (h->E != 1) bad(path, "dimension E (emitters) is " + std::to_string(h->E) + ", expected 1");
  if (h->M < 4) bad(path, "dimension M (measurements) is " + std::to_string(h->M) + ", fewer than 4");
  if (h->M > HrtfSet::kMaxMeasurements)
    bad(path, "dimension M (measurements) is " + std::to_string(h->M) + ", more than " +
                  std::to_string(HrtfSet::kMaxMeasurements));
  if (h->N == 0) bad(path, "dimension N (taps) is 0: empty impulse responses");
  if (h->N > HrtfSet::kMaxLength)
    bad(path, "dimension N (taps) is " + std::to_string(h->N) + ", more than " + std::to_string(HrtfSet::kMaxLength));
  if (std::size_t{h->M} * h->R * h->N > HrtfSet::kMaxSamples)
    bad(path, "M x R x N = " + std::to_string(std::size_t{h->M} * h->R * h->N) + " samples, more than " +
                  std::to_string(HrtfSet::kMaxSamples));
  // libmysofa checks the attributes, not that each array holds what the
  // dimensions say (found by fuzz_sofa: a Data.IR of one value for M x R x N).
  const auto holds = [](const MYSOFA_ARRAY& a, std::size_t n) { return a.values && a.elements == n; };
  if (!holds(h->DataIR, std::size_t{h->M} * h->R * h->N))
    bad(path, "Data.IR holds " + std::to_string(h->DataIR.elements) + " values, not M x R x N = " +
                  std::to_string(std::size_t{h->M} * h->R * h->N));
  if (!holds(h->SourcePosition, std::size_t{h->M} * 3))
    bad(path, "SourcePosition holds " + std::to_string(h->SourcePosition.elements) + " values, not M x 3 = " +
                  std::to_string(std::size_t{h->M} * 3));
}

/// libmysofa's check, with receiver 0 made the left ear where the file has
/// the right ear first; the file's rate; Cartesian positions; finite data.
double check_contents(const std::filesystem::path& path, MYSOFA_HRTF* h) {
  int err = mysofa_check(h);
  float* ears = h->ReceiverPosition.values;
  if (err == MYSOFA_INVALID_RECEIVER_POSITIONS && h->ReceiverPosition.elements >= 6 && ears[1] < 0.0f &&
      ears[4] > 0.0f) {
    // Receiver 0 is the right ear (SOFA's y points left): swap the ears,
    // their positions, responses and delays, so receiver 0 is the left one
    // as libmysofa and everything below expect. (libmysofa itself accepts
    // y < 0 only from old versions of the ARI API, which wrote the ears'
    // positions the wrong way round but their data left first; those pass
    // the check above untouched.)
    for (std::size_t c = 0; c < 3; ++c) std::swap(ears[c], ears[3 + c]);
    for (std::size_t m = 0; m < h->M; ++m)
      std::swap_ranges(h->DataIR.values + 2 * m * h->N, h->DataIR.values + (2 * m + 1) * h->N,
                       h->DataIR.values + (2 * m + 1) * h->N);
    if (h->DataDelay.values && (h->DataDelay.elements == 2 || h->DataDelay.elements == 2 * std::size_t{h->M}))
      for (std::size_t i = 0; i < h->DataDelay.elements; i += 2) std::swap(h->DataDelay.values[i], h->DataDelay.values[i + 1]);
    err = mysofa_check(h);
  }
  if (err == MYSOFA_INVALID_RECEIVER_POSITIONS)
    bad(path, "ReceiverPosition must hold the two ears at (0, a, 0) and (0, -a, 0) (metres, y to the left), "
              "in either order");
  if (err != MYSOFA_OK) bad(path, mysofa_error_text(err));
  if (h->DataSamplingRate.elements < 1) bad(path, "no Data.SamplingRate");
  const double file_rate = h->DataSamplingRate.values[0];
  if (!(file_rate >= 8000.0 && file_rate <= 192000.0))
    bad(path, "unsupported sampling rate " + std::to_string(file_rate) + " Hz in the file");
  mysofa_tocartesian(h);
  for (std::size_t i = 0; i < std::size_t{h->R} * h->M * h->N; ++i)
    if (!std::isfinite(h->DataIR.values[i])) bad(path, "impulse responses hold non-finite samples");
  return file_rate;
}

}  // namespace

/// An opened, checked SOFA file and which of its measurements are kept.
struct HrtfSet::Loading {
  std::filesystem::path path;
  MYSOFA_HRTF* h = nullptr;
  double file_rate = 0.0;
  std::vector<std::uint32_t> keep;  // the measurements used: shell by shell, file order within one
  std::vector<ShellData> shells;    // farthest first; their info indexes `keep`

  [[nodiscard]] const float* position(std::size_t m) const {  // of kept measurement m: x front, y left, z up
    return h->SourcePosition.values + 3 * std::size_t{keep[m]};
  }
  [[nodiscard]] std::span<const float> response(std::size_t i) const {  // i = 2 m + ear of the kept ones
    return {h->DataIR.values + (2 * std::size_t{keep[i / 2]} + i % 2) * h->N, h->N};
  }
};

// A set measured at several distances keeps every shell, farthest first
// (the far field the renderer models for any source beyond it; nearer
// shells serve nearer sources). Shells are told apart by a gap of more
// than 10% between sorted radii, so a single distance measured with some
// scatter stays one shell.
void HrtfSet::find_shells(Loading& f) {
  MYSOFA_HRTF* h = f.h;
  std::vector<double> radius(h->M);
  for (std::size_t m = 0; m < h->M; ++m) {
    const float* p = h->SourcePosition.values + 3 * m;  // SOFA cartesian: x front, y left, z up
    radius[m] = std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
    if (!(radius[m] > 0.0) || !std::isfinite(radius[m]))
      bad(f.path, "source position " + std::to_string(m) + " is not a direction");
  }
  std::vector<double> sorted = radius;
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> inner{sorted.front()};  // each shell's nearest radius, ascending
  for (std::size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i] > 1.1 * sorted[i - 1]) inner.push_back(sorted[i]);
  for (std::size_t g = inner.size(); g-- > 0;) {
    const double hi = g + 1 < inner.size() ? inner[g + 1] : std::numeric_limits<double>::infinity();
    std::vector<std::uint32_t> members;
    double sum = 0.0;
    for (std::uint32_t m = 0; m < h->M; ++m)
      if (radius[m] >= inner[g] && radius[m] < hi) members.push_back(m), sum += radius[m];
    const bool farthest = f.shells.empty();
    if (members.size() < 4) {
      if (farthest)
        bad(f.path, "the farthest measurement distance has " + std::to_string(members.size()) +
                        " measurements, fewer than 4");
      continue;  // a nearer shell too sparse to blend: dropped
    }
    std::vector<Vec3> unit(members.size());
    for (std::size_t k = 0; k < members.size(); ++k) {
      const float* p = h->SourcePosition.values + 3 * std::size_t{members[k]};
      unit[k] = {p[0] / radius[members[k]], p[1] / radius[members[k]], p[2] / radius[members[k]]};
    }
    ShellData shell;
    try {
      shell.triangulation = std::make_shared<const SphereTriangulation>(unit);
    } catch (const std::invalid_argument& e) {
      if (farthest) bad(f.path, std::string("cannot triangulate the measured directions: ") + e.what());
      continue;  // a nearer shell that is a ring or a hemisphere: dropped
    }
    shell.info = {sum / static_cast<double>(members.size()), f.keep.size(), members.size()};
    f.keep.insert(f.keep.end(), members.begin(), members.end());
    f.shells.push_back(std::move(shell));
  }
}

// The kept responses at the render rate, scaled so that white noise from
// straight ahead keeps its level; their directions.
void HrtfSet::read_responses(const Loading& f) {
  const std::size_t M = f.keep.size();
  const std::size_t file_n = f.h->N;
  if (std::abs(f.file_rate - rate_) > 0.5) {
    // Our own resampler rather than mysofa_resample: one kernel per output
    // sample serves every response (a fifth of the time), and Data.Delay is
    // left in the file's samples, rescaled once (file_delay below;
    // mysofa_resample rescales it too, so it was scaled twice).
    const std::size_t out_n = IrResampler::out_length_for(f.file_rate, rate_, file_n);
    if (2 * M * out_n > kMaxSamples)
      bad(f.path, "M x R x N at the render rate = " + std::to_string(2 * M * out_n) + " samples, more than " +
                      std::to_string(kMaxSamples) + " (N = " + std::to_string(file_n) + " taps at " +
                      std::to_string(f.file_rate) + " Hz become " + std::to_string(out_n) + ")");
    const IrResampler rs(f.file_rate, rate_, file_n);
    hrirs_.assign(2 * M * rs.out_length(), 0.0f);
    for (std::size_t i = 0; i < 2 * M; ++i)
      rs.process(f.response(i), std::span<float>(hrirs_.data() + i * rs.out_length(), rs.out_length()));
    length_ = rs.out_length();
  } else {
    hrirs_.reserve(2 * M * file_n);
    for (std::size_t i = 0; i < 2 * M; ++i) hrirs_.insert(hrirs_.end(), f.response(i).begin(), f.response(i).end());
    length_ = file_n;
  }
  const std::size_t N = length_;
  hrir_length_ = N;
  {
    // The frontal measurement's mean ear energy becomes 1. One scale for the
    // whole set, so every interaural cue is kept.
    std::size_t front = 0;
    double best = -2.0;
    for (std::size_t m = 0; m < f.shells.front().info.count; ++m) {
      const float* p = f.position(m);
      const double r = std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
      if (r > 0.0 && p[0] / r > best) best = p[0] / r, front = m;
    }
    double e = 0.0;
    for (std::size_t i = 0; i < 2 * N; ++i) e += double(hrirs_[2 * front * N + i]) * hrirs_[2 * front * N + i];
    const double scale = e > 0.0 ? std::sqrt(2.0 / e) : 1.0;
    for (float& v : hrirs_) v = static_cast<float>(v * scale);
  }
  dirs_.resize(M);
  for (std::size_t m = 0; m < M; ++m) {
    const float* p = f.position(m);
    const double x = p[0], y = p[1], z = p[2];
    const double r = std::sqrt(x * x + y * y + z * z);  // > 0, checked in find_shells
    dirs_[m] = {std::atan2(y, x), std::asin(z / r)};
  }
}

// Each ear's filter is its HRIR read from `margin` samples before its
// (fractional) onset on, and the delay is that shift: filter + delay give
// back the measured HRIR, and every filter has its onset at the same place,
// so blending neighbours adds aligned responses, not combs. The margin
// kept before each onset is one for the whole set (so every filter has its
// onset at the same place) and long enough that no response loses what
// comes before its onset: band-limited measurements ring before it
// (pre-ringing), and a filter cut at two samples before the onset dropped
// that (error energy -21 dB on a synthetic set; see
// tests/unit/hrtf/test_sofa_variety.cpp). Each shell's own flight time
// (its earliest arrival) is latency, not a cue: removed from its delays
// (shell 0's is removed_delay_s()).
void HrtfSet::split_onsets(const Loading& f) {
  const std::size_t M = f.keep.size(), N = hrir_length_;
  // Data.Delay (samples at the file's rate) adds to each ear: 1 x R or M x R.
  const auto file_delay = [&](std::size_t m, std::size_t ear) -> double {
    const auto& d = f.h->DataDelay;
    if (d.elements == 2) return d.values[ear] * rate_ / f.file_rate;
    if (d.elements == 2 * std::size_t{f.h->M}) return d.values[2 * std::size_t{f.keep[m]} + ear] * rate_ / f.file_rate;
    return 0.0;
  };
  std::vector<double> onsets(2 * M);
  double margin = 2.0;
  for (std::size_t i = 0; i < 2 * M; ++i) {
    const std::span<const float> hrir(hrirs_.data() + i * N, N);
    onsets[i] = onset_of(hrir);
    margin = std::max(margin, onsets[i] - static_cast<double>(first_audible(hrir)));
  }
  // A shift may be negative (a response whose onset comes sooner than the
  // margin starts with silence): the filters are longer than the responses
  // by what such a shift pushes past their end, so no tail is cut either.
  const double earliest = *std::min_element(onsets.begin(), onsets.end());
  const std::size_t L = N + static_cast<std::size_t>(std::ceil(std::max(0.0, margin - earliest)));
  length_ = L;
  filters_.assign(2 * M * L, 0.0f);
  std::vector<std::array<double, 2>> raw(M);
  for (std::size_t m = 0; m < M; ++m)
    for (std::size_t ear = 0; ear < 2; ++ear) {
      const std::span<const float> hrir(hrirs_.data() + (2 * m + ear) * N, N);
      const double shift = onsets[2 * m + ear] - margin;
      shift_earlier(hrir, shift, std::span<float>(filters_.data() + (2 * m + ear) * L, L));
      raw[m][ear] = shift + file_delay(m, ear);
    }
  delays_.resize(M);
  for (std::size_t s = 0; s < f.shells.size(); ++s) {
    const auto& info = f.shells[s].info;
    double min_delay = std::numeric_limits<double>::infinity();
    for (std::size_t m = info.first; m < info.first + info.count; ++m) min_delay = std::min({min_delay, raw[m][0], raw[m][1]});
    if (s == 0) removed_delay_s_ = min_delay / rate_;
    for (std::size_t m = info.first; m < info.first + info.count; ++m)
      delays_[m] = {(raw[m][0] - min_delay) / rate_, (raw[m][1] - min_delay) / rate_};
  }
}

// Each filter's energy per ear, and each triangle's table of its three
// filters' inner products (each pair of measurements, a vertex with itself
// or an edge shared by two triangles, multiplied out once).
void HrtfSet::tabulate_energies(std::vector<ShellData>& shells) {
  const std::size_t M = dirs_.size();
  energies_.resize(M);
  for (std::size_t m = 0; m < M; ++m) {
    for (std::size_t ear = 0; ear < 2; ++ear) {
      double e = 0.0;
      for (float v : filter(m, static_cast<Ear>(ear))) e += double(v) * v;
      energies_[m][ear] = std::max(e, 1e-30);  // log-safe for a silent ear
    }
    log_energies_.push_back({std::log(energies_[m][0]), std::log(energies_[m][1])});
  }
  std::unordered_map<std::uint64_t, std::array<double, 2>> pair_dots;
  const auto pair_dot = [&](std::uint32_t i, std::uint32_t j) {
    const std::uint64_t key = (std::uint64_t{std::min(i, j)} << 32) | std::max(i, j);
    auto [it, fresh] = pair_dots.try_emplace(key);
    if (fresh)
      for (std::size_t ear = 0; ear < 2; ++ear)
        it->second[ear] = detail::dot_double(filter(i, static_cast<Ear>(ear)), filter(j, static_cast<Ear>(ear)));
    return it->second;
  };
  for (auto& shell : shells) {
    const SphereTriangulation& tri = *shell.triangulation;
    const auto first = static_cast<std::uint32_t>(shell.info.first);
    shell.gram.resize(tri.triangle_count());
    for (std::size_t t = 0; t < tri.triangle_count(); ++t) {
      const auto v = tri.vertices(t);
      constexpr std::array<std::array<int, 2>, 6> kPairs{{{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}}};
      for (std::size_t k = 0; k < 6; ++k) {
        const auto d = pair_dot(first + v[kPairs[k][0]], first + v[kPairs[k][1]]);
        for (std::size_t ear = 0; ear < 2; ++ear) shell.gram[t][ear][k] = d[ear];
      }
    }
  }
}

HrtfSet HrtfSet::load(const std::filesystem::path& path, double sample_rate) {
  precheck_file(path, sample_rate);
  int err = 0;
  SofaPtr sofa(mysofa_load(path.c_str(), &err));
  if (!sofa || err != MYSOFA_OK) bad(path, mysofa_error_text(err));
  Loading f;
  f.path = path;
  f.h = sofa.get();
  check_dimensions(path, f.h);
  f.file_rate = check_contents(path, f.h);
  find_shells(f);

  HrtfSet set;
  set.rate_ = sample_rate;
  set.read_responses(f);
  set.split_onsets(f);
  set.tabulate_energies(f.shells);
  set.shells_ = std::move(f.shells);
  set.set_filter_blend(FilterBlend::floored);
  return set;
}

void HrtfSet::set_filter_blend(FilterBlend blend) {
  blend_ = blend;
  for (ShellData& sh : shells_) {
    const SphereTriangulation& tri = *sh.triangulation;
    sh.floor.assign(tri.triangle_count(), 0.0);
    if (blend != FilterBlend::floored) continue;
    for (std::size_t t = 0; t < tri.triangle_count(); ++t) {
      const auto v = tri.vertices(t);
      std::array<Vec3, 3> p{};
      for (std::size_t k = 0; k < 3; ++k) {
        const Direction& d = dirs_[sh.info.first + v[k]];
        p[k] = unit_vector(d.azimuth, d.elevation);
      }
      double longest = 0.0;  // radians
      for (std::size_t k = 0; k < 3; ++k) {
        const Vec3& a = p[k];
        const Vec3& b = p[(k + 1) % 3];
        longest = std::max(longest, std::acos(std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0)));
      }
      const double shift = kSpectralShiftDeg * std::numbers::pi / 180.0;
      sh.floor[t] = longest > 0.0 ? std::min(kMaxBlendFloor, shift / (2.0 * longest)) : 0.0;
    }
  }
}

HrtfSet::Stored HrtfSet::stored() const {
  Stored s;
  s.rate = rate_;
  s.filter_length = length_;
  s.hrir_length = hrir_length_;
  s.removed_delay_s = removed_delay_s_;
  s.directions = dirs_;
  s.filters = filters_;
  s.hrirs = hrirs_;
  s.delays = delays_;
  s.energies = energies_;
  for (const ShellData& sh : shells_) s.shells.push_back({sh.info, sh.triangulation->stored(), sh.gram});
  return s;
}

HrtfSet HrtfSet::from_stored(Stored s) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("stored HRTF set: " + what); };
  const auto finite = [](double x) { return std::isfinite(x); };
  if (!(s.rate >= 8000.0 && s.rate <= 192000.0)) fail("sample rate " + std::to_string(s.rate) + " out of range");
  const std::size_t M = s.directions.size();
  if (M < 4 || M > kMaxMeasurements) fail(std::to_string(M) + " measurements");
  // Each bound before the product that uses it, so nothing overflows.
  if (s.filter_length == 0 || s.filter_length > kMaxSamples || s.hrir_length == 0 || s.hrir_length > s.filter_length)
    fail("filter length " + std::to_string(s.filter_length) + ", response length " + std::to_string(s.hrir_length));
  if (s.filters.size() != 2 * M * s.filter_length) fail("filters: " + std::to_string(s.filters.size()) + " samples");
  if (s.hrirs.size() != 2 * M * s.hrir_length) fail("responses: " + std::to_string(s.hrirs.size()) + " samples");
  if (s.delays.size() != M || s.energies.size() != M) fail("delays or energies not one per measurement");
  if (!finite(s.removed_delay_s)) fail("removed delay not finite");
  for (const Direction& d : s.directions)
    if (!finite(d.azimuth) || !finite(d.elevation)) fail("a direction is not finite");
  for (const Delays& d : s.delays)
    if (!finite(d.left_s) || !finite(d.right_s) || d.left_s < 0.0 || d.right_s < 0.0) fail("a delay is negative or not finite");
  for (const auto& e : s.energies)
    if (!(e[0] > 0.0 && finite(e[0]) && e[1] > 0.0 && finite(e[1]))) fail("an energy is not positive and finite");
  if (s.shells.empty()) fail("no shells");
  HrtfSet set;
  std::size_t next = 0;
  for (StoredShell& sh : s.shells) {
    if (sh.info.first != next || sh.info.count < 4 || sh.info.count > M - next)
      fail("the shells do not tile the measurements (shell at " + std::to_string(sh.info.first) + ")");
    next += sh.info.count;
    if (!(sh.info.radius_m > 0.0) || !finite(sh.info.radius_m)) fail("a shell's distance is not positive and finite");
    ShellData data;
    data.info = sh.info;
    data.triangulation = std::make_shared<const SphereTriangulation>(
        SphereTriangulation::from_stored(std::move(sh.triangulation), sh.info.count));
    if (sh.gram.size() != data.triangulation->triangle_count()) fail("a Gram table is not one per triangle");
    for (const auto& t : sh.gram)
      for (const auto& ear : t)
        for (const double g : ear)
          if (!finite(g)) fail("a Gram table entry is not finite");
    data.gram = std::move(sh.gram);
    set.shells_.push_back(std::move(data));
  }
  if (next != M) fail("the shells hold " + std::to_string(next) + " of " + std::to_string(M) + " measurements");
  set.rate_ = s.rate;
  set.length_ = s.filter_length;
  set.hrir_length_ = s.hrir_length;
  set.removed_delay_s_ = s.removed_delay_s;
  set.dirs_ = std::move(s.directions);
  set.filters_ = std::move(s.filters);
  set.hrirs_ = std::move(s.hrirs);
  set.delays_ = std::move(s.delays);
  set.energies_ = std::move(s.energies);
  set.log_energies_.reserve(M);
  for (const auto& e : set.energies_) set.log_energies_.push_back({std::log(e[0]), std::log(e[1])});
  set.set_filter_blend(FilterBlend::floored);
  return set;
}

Interpolation HrtfSet::interpolate(double azimuth, double elevation, std::uint32_t hint) const {
  return interpolate(unit_vector(azimuth, elevation), hint);
}

std::size_t HrtfSet::nearest_shell(double distance_m) const {
  std::size_t best = 0;
  for (std::size_t s = 1; s < shells_.size(); ++s)
    if (std::abs(distance_m - shells_[s].info.radius_m) < std::abs(distance_m - shells_[best].info.radius_m)) best = s;
  return best;
}

Interpolation HrtfSet::interpolate_in_shell(const Vec3& d, std::size_t shell, std::uint32_t hint) const {
  const ShellData& sh = shells_[std::min(shell, shells_.size() - 1)];
  Interpolation out;
  out.blend = sh.triangulation->locate(d, hint);
  for (auto& i : out.blend.index) i += static_cast<std::uint32_t>(sh.info.first);
  std::array<double, 2> log_energy{0.0, 0.0};  // the weighted mean of the measured ears' log energies
  for (std::size_t k = 0; k < 3; ++k) {
    const double w = out.blend.weight[k];
    const std::size_t m = out.blend.index[k];
    out.delays.left_s += w * delays_[m].left_s;
    out.delays.right_s += w * delays_[m].right_s;
    log_energy[0] += w * log_energies_[m][0];
    log_energy[1] += w * log_energies_[m][1];
  }
  out.energy = {std::exp(log_energy[0]), std::exp(log_energy[1])};
  out.barycentric = out.blend.weight;
  // The filter blend: weights below the triangle's floor fade out
  // (kSpectralShiftDeg). Continuous in the direction, so a moving source's
  // gains still glide; at the floor's limit of 1/3 the centre keeps 1/3 each.
  if (const double floor = sh.floor[out.blend.triangle]; floor > 0.0) {
    std::array<double, 3> kept{};
    double sum = 0.0;
    for (std::size_t k = 0; k < 3; ++k) sum += kept[k] = std::max(0.0, out.blend.weight[k] - floor);
    if (sum > 0.0)
      for (std::size_t k = 0; k < 3; ++k) out.blend.weight[k] = kept[k] / sum;
  }
  if (blend_ == FilterBlend::nearest) {
    const auto& b = out.barycentric;
    const auto k = static_cast<std::size_t>(std::max_element(b.begin(), b.end()) - b.begin());
    out.blend.weight = {};
    out.blend.weight[k] = 1.0;
  }
  const std::array<double, 3>& w = out.blend.weight;
  for (std::size_t ear = 0; ear < 2; ++ear) {
    const auto& g = sh.gram[out.blend.triangle][ear];  // w^T G w
    out.blend_energy[ear] = w[0] * w[0] * g[0] + w[1] * w[1] * g[1] + w[2] * w[2] * g[2] +
                            2.0 * (w[0] * w[1] * g[3] + w[0] * w[2] * g[4] + w[1] * w[2] * g[5]);
  }
  if (parametric_radius_) {
    const double azimuth = std::atan2(d[1], d[0]), elevation = std::asin(std::clamp(d[2], -1.0, 1.0));
    const double mid = 0.5 * (out.delays.left_s + out.delays.right_s);
    const double itd = woodworth_itd(azimuth, elevation, *parametric_radius_);
    out.delays = {mid - 0.5 * itd, mid + 0.5 * itd};
    // Keep both delays non-negative (a constant shift is latency, not a cue).
    const double lo = std::min(out.delays.left_s, out.delays.right_s);
    if (lo < 0.0) out.delays = {out.delays.left_s - lo, out.delays.right_s - lo};
  }
  return out;
}

Delays HrtfSet::lookup(double azimuth, double elevation, std::span<float> left, std::span<float> right) const {
  const Interpolation in = interpolate(azimuth, elevation);
  std::fill(left.begin(), left.end(), 0.0f);
  std::fill(right.begin(), right.end(), 0.0f);
  const std::size_t n = std::min({length_, left.size(), right.size()});
  for (std::size_t k = 0; k < 3; ++k) {
    const auto w = static_cast<float>(in.blend.weight[k]);
    if (w == 0.0f) continue;
    const float* fl = filters_.data() + (2 * in.blend.index[k]) * length_;
    const float* fr = fl + length_;
    for (std::size_t i = 0; i < n; ++i) {
      left[i] += w * fl[i];
      right[i] += w * fr[i];
    }
  }
  for (std::size_t ear = 0; ear < 2; ++ear) {
    const std::span<float> f = ear == 0 ? left : right;
    double e = 0.0;
    for (std::size_t i = 0; i < n; ++i) e += double(f[i]) * f[i];
    if (e > 0.0) {
      const auto g = static_cast<float>(std::sqrt(in.energy[ear] / e));
      for (std::size_t i = 0; i < n; ++i) f[i] *= g;
    }
  }
  return in.delays;
}

}  // namespace earshot::hrtf
