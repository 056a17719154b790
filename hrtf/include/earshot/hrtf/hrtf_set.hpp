// A set of head-related impulse responses loaded from a SOFA file, ready for
// rendering: resampled to the render rate, each HRIR split into an onset
// delay per ear (the ITD lives there) and an onset-free filter, and any
// direction interpolated from the measured ones.
//
// Onset split: an ear's onset is where it first reaches -20 dB of that
// HRIR's peak, interpolated between samples; the filter is the HRIR read
// from a margin before that (band-limited, so a fractional shift) and the
// delay is that shift. The margin is one for the whole set (every filter has
// its onset at the same place) and covers what any response holds before its
// onset down to -60 dB of its energy (band-limited measurements ring ahead of
// the onset; KEMAR about 20 samples), so the filters are that much longer
// than the responses and nothing is cut at either end. Rendering filter(ear) delayed by delay(ear) therefore
// gives back the measured HRIR, so measured ITD and ILD are kept (to 0.1 us
// and 0.04 dB, measured on rendered noise). The shift common to all measurements (the measurement rig's
// flight time) is removed from every delay: it is latency, not a cue.
//
// Interpolation: the measured directions are triangulated on the sphere
// (sphere_triangulation.hpp); a direction takes barycentric weights of its
// triangle, applied to the onset-free filters and, separately, to the
// delays, so interpolation never sums two copies at different delays
// (no comb filtering). Each ear's blended filter is then rescaled to the
// energy interpolated in dB between the measurements, so the broadband ILD
// moves smoothly between them. Directions below the lowest measured ring
// blend that ring's measurements.
//
// Level: the whole set is scaled so that white noise from straight ahead
// keeps its level (the frontal HRIRs' mean ear energy is 1).
//
// What the file holds: a set measured at several distances keeps every
// shell (shells: radii separated by gaps of more than 10%; a shell's
// distance is the mean of its radii). Shell 0 is the farthest: measurement
// indices 0 .. measurement_count() - 1, and what the plain interpolate()
// blends, as for a single-distance set; nearer shells follow it in the
// indices (all_measurement_count() counts every shell), each triangulated on
// its own. The renderer reads a source's HRTFs from the shell nearest its
// distance (nearest_shell(); no blending between shells: crossing the
// midpoint between two shells glides from one to the other over two blocks,
// as crossing between triangles does) and corrects only from that shell's
// distance to the source's (earshot/audio/near_field.hpp). A nearer shell
// that cannot be triangulated (fewer than 4 directions, a ring, a
// hemisphere) is dropped. One level for the whole set (from shell 0's front),
// so nearer shells keep the level differences the file gives them; each
// shell's own common flight time is removed from its delays. Receiver 0 may be
// either ear: ReceiverPosition's y (to the left) says which, and a set with
// the right ear first is swapped on load.
//
// Conventions: SOFA's. Azimuth counter-clockwise from the front (pi/2 =
// left), elevation up, radians. Delays in seconds.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "earshot/hrtf/sphere_triangulation.hpp"

namespace earshot::hrtf {

struct Delays {
  double left_s = 0.0;
  double right_s = 0.0;
};

struct Direction {
  double azimuth = 0.0;    ///< radians, counter-clockwise from the front
  double elevation = 0.0;  ///< radians, up
};

enum class Ear { left = 0, right = 1 };

/// How a direction is made from the measurements: which three and their
/// weights, the interpolated delays, and the energy each ear's blended filter
/// should have (interpolated in dB; the blend itself loses some mid-way).
struct Interpolation {
  /// The filter blend: the triangle's measurements and the weights their
  /// filters are mixed with. Weights below the triangle's floor are faded
  /// out (see HrtfSet::kSpectralShiftDeg), so a direction usually mixes two
  /// filters and near a measurement one; a measured direction is always
  /// that measurement alone.
  Blend blend;
  /// The triangle's plain barycentric weights (same order as blend.index):
  /// what `delays` and `energy` are interpolated with, so the ITD and each
  /// ear's broadband level follow the direction exactly.
  std::array<double, 3> barycentric{};
  Delays delays;
  std::array<double, 2> energy{1.0, 1.0};  ///< [left, right], sum of squared taps
  /// [left, right] energy of the plain weighted sum of the three filters.
  std::array<double, 2> blend_energy{1.0, 1.0};
  /// The gain that brings an ear's weighted sum to `energy`: scale the
  /// weights by it and the blend needs no second pass.
  [[nodiscard]] double ear_gain(std::size_t ear) const {
    return blend_energy[ear] > 0.0 ? std::sqrt(energy[ear] / blend_energy[ear]) : 1.0;
  }
};

/// Head radii of the thesis's listener sizes.
enum class HeadSize { small, medium, large };
[[nodiscard]] double head_radius_m(HeadSize s);

/// Woodworth's spherical-head ITD (seconds, left ear minus right ear
/// arrival: positive when the left ear hears first, i.e. source on the left).
[[nodiscard]] double woodworth_itd(double azimuth, double elevation, double head_radius_m,
                                   double speed_of_sound = 343.0);

class HrtfSet {
 public:
  /// The MIT KEMAR set installed by Debian's libmysofa1.
  static constexpr const char* kDefaultPath = "/usr/share/libmysofa/MIT_KEMAR_normal_pinna.sofa";

  // What the loader accepts, checked before any work that grows with them
  // (measured databases sit inside: ARI 1550 and CIPIC 1250 directions,
  // SADIE II 8802, FABIAN 11950; 32-2048 taps, long room-like sets 8192 at
  // 48 kHz = 0.17 s. A simulated 1-degree grid, 64800, is refused).
  /// Measurements (M). Also what the triangulation (quadratic in M at load)
  /// finishes in seconds.
  static constexpr std::size_t kMaxMeasurements = 20000;
  /// Taps per response (N) at the file's rate: 0.34 s at 192 kHz.
  static constexpr std::size_t kMaxLength = 65536;
  /// Samples in the whole set (M x 2 x N), at the file's rate and again at
  /// the render rate: 2^25, 128 MB as float (11950 x 2 x 1404, or 2048
  /// directions of 8192 taps).
  static constexpr std::size_t kMaxSamples = std::size_t{1} << 25;
  /// File size: 1 GiB (the largest set above as doubles is under 300 MB).
  static constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t{1} << 30;

  /// Loads a SOFA file of the SimpleFreeFieldHRIR convention and resamples
  /// it to `sample_rate` (8-192 kHz). Throws earshot::InputError naming the
  /// file and the problem (missing, not SOFA, truncated, other convention,
  /// not two ears (R must be 2) and one emitter (E = 1), unsupported rate,
  /// a size beyond the limits above, naming the dimension).
  [[nodiscard]] static HrtfSet load(const std::filesystem::path& sofa, double sample_rate);
  [[nodiscard]] static HrtfSet load_default(double sample_rate) { return load(kDefaultPath, sample_rate); }

  /// The version of what load() computes from a file. Bump it with any
  /// change to load() (or to what it calls: the resampler, the onset split,
  /// the triangulation) that changes its arrays, so sets prepared by an
  /// older build and kept on disk are prepared again
  /// (earshot/audio/hrtf_disk_cache.hpp).
  static constexpr std::uint32_t kPreparationVersion = 1;

  /// How far (degrees) the filter blend may move the spectral detail from
  /// the direction asked for. A blend of three measurements costs three
  /// convolutions per ear; fading out weights below a floor tau
  /// (w' = max(0, w - tau), renormalised) leaves one or two for most
  /// directions, and moves the blend's point within the triangle by at
  /// most 2 tau of its longest edge (the total variation between w and w'
  /// is at most 2 tau). So each triangle's floor is
  /// min(kMaxBlendFloor, kSpectralShiftDeg / (2 x longest edge)): dense
  /// grids fade more, sparse ones (and the faces that span a gap in the
  /// grid) stay nearly barycentric. 3 degrees is below the smallest change
  /// of elevation listeners hear in broadband noise, ~3.6 degrees (Perrott
  /// and Saberi 1990), where the spectral detail is the cue; the ITD and
  /// the broadband level of each ear, the horizontal cues, are interpolated
  /// with the plain weights and do not move at all.
  static constexpr double kSpectralShiftDeg = 3.0;
  /// The floor never reaches 1/3, where the centre of a triangle would have
  /// no weight left.
  static constexpr double kMaxBlendFloor = 0.3;
  /// How the filters of a direction's triangle are mixed. The ITD and each
  /// ear's broadband level always take the plain barycentric weights; only
  /// the spectral detail differs. load() and from_stored() set `floored`.
  enum class FilterBlend {
    floored,  ///< weights below the triangle's floor fade out (above): the default
    plain,    ///< the barycentric weights, three filters inside a triangle (for comparisons)
    /// The measurement with the largest barycentric weight alone: one filter
    /// per ear, the spectral detail jumping at the bisectors between
    /// measurements (a renderer's gains still ramp across a block, so the
    /// jump is a one-block crossfade, as OpenAL Soft does it). For the
    /// throughput bench: what one convolution per ear would cost.
    nearest,
  };
  void set_filter_blend(FilterBlend blend);
  [[nodiscard]] FilterBlend filter_blend() const { return blend_; }

  [[nodiscard]] double sample_rate() const { return rate_; }
  /// Taps of every onset-free filter: the responses' length plus room for
  /// the margin kept before the earliest onset.
  [[nodiscard]] std::size_t filter_length() const { return length_; }
  /// Measurements of the farthest shell (shell 0), indices 0 .. this - 1.
  [[nodiscard]] std::size_t measurement_count() const { return shells_.front().info.count; }
  /// Measurements of every shell: filter(), delays() and direction() take
  /// any index below this.
  [[nodiscard]] std::size_t all_measurement_count() const { return dirs_.size(); }

  /// The measurement distances, farthest first.
  struct Shell {
    double radius_m = 0.0;
    std::size_t first = 0, count = 0;  ///< its measurement indices
  };
  [[nodiscard]] std::size_t shell_count() const { return shells_.size(); }
  [[nodiscard]] const Shell& shell(std::size_t s) const { return shells_[s].info; }
  /// The shell whose distance is nearest `distance_m` (0 beyond the farthest).
  [[nodiscard]] std::size_t nearest_shell(double distance_m) const;
  [[nodiscard]] Direction direction(std::size_t i) const { return dirs_[i]; }
  /// The measured onset-free filter of measurement i.
  [[nodiscard]] std::span<const float> filter(std::size_t i, Ear ear) const;
  [[nodiscard]] Delays delays(std::size_t i) const { return delays_[i]; }
  /// The flight time common to shell 0's measurements, removed from their
  /// delays (each nearer shell has its own removed likewise).
  [[nodiscard]] double removed_delay_s() const { return removed_delay_s_; }
  /// The original (resampled) HRIR of measurement i, before the onset split.
  [[nodiscard]] std::span<const float> measured_hrir(std::size_t i, Ear ear) const;

  /// Filters and delays for any direction; `left` and `right` must hold
  /// filter_length() samples. Does not allocate.
  Delays lookup(double azimuth, double elevation, std::span<float> left, std::span<float> right) const;

  /// The recipe for any direction without blending the filters (callers
  /// that keep the measurements in another form, e.g. as spectra, blend
  /// them by `blend` and scale each ear to `energy`). Does not allocate.
  /// `hint`: the previous call's blend.triangle for the same source.
  [[nodiscard]] Interpolation interpolate(double azimuth, double elevation,
                                          std::uint32_t hint = SphereTriangulation::kNoHint) const;
  /// The same for a unit vector in SOFA's frame (x ahead, y left, z up):
  /// no trigonometry unless the ITD is parametric.
  [[nodiscard]] Interpolation interpolate(const Vec3& direction,
                                          std::uint32_t hint = SphereTriangulation::kNoHint) const {
    return interpolate_in_shell(direction, 0, hint);
  }
  /// The same within shell `shell` (its blend names measurement indices of
  /// that shell; `hint` a triangle of it).
  [[nodiscard]] Interpolation interpolate_in_shell(const Vec3& direction, std::size_t shell,
                                          std::uint32_t hint = SphereTriangulation::kNoHint) const;

  /// With a head radius, lookup returns Woodworth delays (both ears around
  /// a common centre) instead of the measured ones; nullopt restores them.
  void set_parametric_itd(std::optional<double> head_radius_m) { parametric_radius_ = head_radius_m; }

  /// The shells as stored: each one's distance, measurement range,
  /// triangulation and Gram table (as in ShellData below).
  struct StoredShell {
    Shell info;
    SphereTriangulation::Stored triangulation;
    std::vector<std::array<std::array<double, 6>, 2>> gram;  // [triangle][ear][00, 11, 22, 01, 02, 12]
  };
  /// Everything load() computes, as plain arrays: what a disk cache of
  /// prepared sets keeps. Not the parametric ITD (a setting, not data).
  struct Stored {
    double rate = 0.0;
    std::size_t filter_length = 0, hrir_length = 0;
    double removed_delay_s = 0.0;
    std::vector<Direction> directions;            // [measurement]
    std::vector<float> filters;                   // [measurement][ear][filter_length]
    std::vector<float> hrirs;                     // [measurement][ear][hrir_length]
    std::vector<Delays> delays;                   // [measurement]
    std::vector<std::array<double, 2>> energies;  // [measurement][ear] of the filters
    std::vector<StoredShell> shells;              // farthest first
  };
  [[nodiscard]] Stored stored() const;
  /// The set `stored()` gave, taken back without recomputing: its renders
  /// are sample for sample those of the original. Checks every size and
  /// what the renderer relies on (finite delays and energies, shells that
  /// tile the measurements, triangles within their shell) and throws
  /// std::invalid_argument naming the array that does not fit.
  [[nodiscard]] static HrtfSet from_stored(Stored s);

 private:
  HrtfSet() = default;

  double rate_ = 0.0;
  std::size_t length_ = 0;       // of the filters
  std::size_t hrir_length_ = 0;  // of the measured responses (the filters may be longer)
  std::vector<Direction> dirs_;
  std::vector<float> filters_;  // [measurement][ear][sample]
  std::vector<float> hrirs_;    // [measurement][ear][sample], as measured
  std::vector<Delays> delays_;
  std::vector<std::array<double, 2>> energies_;  // [measurement][ear] of the filters
  std::vector<std::array<double, 2>> log_energies_;  // their logarithms, blended per direction
  struct ShellData {
    Shell info;
    std::shared_ptr<const SphereTriangulation> triangulation;
    // [triangle][ear][00, 11, 22, 01, 02, 12]: inner products of the
    // triangle's three filters, so a blend's energy costs nine multiplies,
    // not a pass.
    std::vector<std::array<std::array<double, 6>, 2>> gram;
    std::vector<double> floor;  // [triangle]: the blend floor (kSpectralShiftDeg; set_filter_blend)
  };
  std::vector<ShellData> shells_;  // farthest first
  FilterBlend blend_ = FilterBlend::floored;

  // The steps of load(), in order (hrtf_set.cpp).
  struct Loading;                                       // the checked file and what is kept of it
  static void find_shells(Loading& f);                  // the measurements kept, by distance
  void read_responses(const Loading& f);                // hrirs_ at the render rate, scaled; dirs_
  void split_onsets(const Loading& f);                  // filters_ and delays_
  void tabulate_energies(std::vector<ShellData>& shells);  // energies_ and the Gram tables
  double removed_delay_s_ = 0.0;
  std::optional<double> parametric_radius_;
};

}  // namespace earshot::hrtf
