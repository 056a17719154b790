// The filters of a binaural Ambisonic decoder, designed once from a measured
// HRTF set (any SOFA set: hrtf::HrtfSet) for one order and rate.
//
// A decoder is (N+1)^2 FIR filters per ear: ear e's output is
// sum_c h_{e,c} * b_c over the ambiX (ACN, SN3D) input channels b_c. A plane
// wave from direction d then reaches ear e through sum_c Y_c(d) h_{e,c},
// which the design fits to the HRTF of d (measured filter with its delay,
// as the direct renderer plays it) over the set's measured directions.
//
// Methods:
// - ls: least squares at every frequency, weighted by each measurement's
//   share of the sphere (the grid's quadrature, below) and lightly
//   regularised (Tikhonov, `regularisation` times the mean diagonal of the
//   normal matrix: directions the grid does not cover, such as KEMAR's
//   below -40 deg, get a small, smooth response instead of a blow-up).
//   Order N reproduces an HRTF only up to about N c / (2 pi r_head)
//   (~620 Hz per order for an 8.75 cm head); above, the interaural phase
//   of lateral sources is too complex and the fit loses level.
// - magls (Schoerkhuber, Zaunschirm and Hoeldrich 2018, "Binaural
//   rendering of Ambisonic signals via magnitude least squares"): the same
//   LS below `transition_hz` (so the ITD, heard below 1.5 kHz, keeps the
//   HRTF's phase); above it only the magnitudes are fitted, each
//   direction's phase taken from the previous frequency bin's decoder and
//   advanced by each ear's mean group delay (the quadrature-weighted mean
//   energy centroid of the responses), so the high band stays where the
//   responses' energy is instead of gathering around time zero and
//   wrapping. (Without that step the order-3 filters lost energy to the cut
//   at `length` and the ITD below 1.5 kHz was off by up to 800 us.)
// Options on top:
// - shadow_weighting (the default): above the transition, the magnitude
//   fit of each third-octave band gives a direction whose power there is
//   more than `shadow_below_db` (10 dB) below the band's mean the weight
//   of a relative-error fit (quadrature weight x threshold / power, the
//   power floored at -30 dB of the mean); louder directions keep their
//   quadrature weight. Unweighted, the far ear's head shadow, 20-30 dB
//   down, counts for almost nothing in a linear-magnitude fit and is filled
//   in: plain MagLS at order 3 renders KEMAR's ILD 4.3 dB too small at
//   110 deg; shadow-weighted, the worst is 1.9 dB and the mean 0.77 dB
//   (plain: 0.86), with the per-band spectra no worse (mean band error
//   0.88 dB, plain 0.95). Weighting every direction by 1 / power instead
//   (a relative fit everywhere) also brought the worst to 2.0 dB, but at
//   the near ear's expense ahead (1.5 dB ILD errors at +-20 deg, where the
//   plain fit has 0.9) (tests/bench/ambi_cues.cpp, docs/AMBISONICS.md).
// - joint_ear_fit (the default, on top of the shadow weighting): MagLS
//   fits each ear on its own, so their level errors at a direction are
//   unrelated and the ILD errs by their difference: at the sides, where the
//   order-N pattern cannot follow the far ear's shadow (its bright spot at
//   90 deg and the notches either side are detail of higher order: spatial
//   aliasing fills or overshoots them), the near ear is right and the far
//   ear is not. A last stage fits the ears together: per ear and standard
//   third-octave band above the transition a real mix M of the channels'
//   filters (each bin's phase and the band's detail stay MagLS's; every
//   energy pattern an order-N decoder can give the band is reachable),
//   chosen by minimising at once the band level errors (dB, every
//   measurement by its share of the sphere, the horizontal ones twice), each
//   ear's broadband level error and the broadband ILD error at the
//   horizontal measurements (ild_weight, level_weight), with hinges that
//   hold every horizontal ILD error within max(MagLS's, 0.5 dB) and 1 dB and
//   every ear's level error within max(MagLS's, 1 dB). So the ears err
//   together where they must: KEMAR at order 3, worst ILD error 1.3 dB
//   (MagLS alone 1.9), mean 0.55 (0.78), band spectra no worse. How far
//   that can go is bounded: any linear order-N decoder's broadband ear
//   energies on the horizon are trigonometric polynomials of degree 2N, and
//   an ILD closer than this costs each ear's level (docs/AMBISONICS.md, the
//   bound). The stage costs about 0.1 s of one core at order 3, 0.5 s at 5.
// - diffuse_covariance (Zaunschirm, Schoerkhuber and Hoeldrich 2018, JASA
//   143(6)): per bin above the transition, a 2x2 mix of the two ears'
//   filters so that a diffuse field (incoherent waves from everywhere) has
//   the HRTF set's ear powers and interaural coherence. Measured on
//   KEMAR, it worsens plane-wave ILDs at orders 1-4 (order 3: 4.4 dB worst,
//   1.10 mean, against 1.9 and 0.77 without it) and helps a little at 5
//   (1.6 / 0.52 against 2.0 / 0.46), so it is off. (Figures without the
//   joint fit; with both, the mix applies after the joint fit.)
//
// Quadrature: each measurement weighs its spherical Voronoi cell, estimated
// by assigning 2^15 near-uniform points on the sphere (a Fibonacci lattice
// and its mirror image across the median plane) to their nearest
// measurement; a point farther than twice the grid's median
// neighbour spacing from every measurement is in a gap the set does not
// cover and counts for none.
//
// The result is pure data: serialise() / deserialise() give and take a byte
// form (for a disk cache), checked on the way in.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "earshot/hrtf/hrtf_set.hpp"

namespace earshot::ambisonics {

enum class DecoderMethod { ls, magls };

struct DecoderDesign {
  DecoderMethod method = DecoderMethod::magls;
  /// LS below, magnitudes above; 0: order x c / (2 pi 8.75 cm), ~624 Hz per
  /// order, at most 2 kHz (624, 1248, 1872, 2000, 2000 Hz for orders 1-5).
  /// Above ~2 kHz the order-N LS fills in the far ear's shadow at the sides
  /// (orders 4 and 5: the worst horizontal ILD error 2.8 and 2.7 dB at 2.5
  /// and 3.1 kHz, 2.5 and 2.0 dB at 2 kHz).
  double transition_hz = 0.0;
  bool shadow_weighting = true;
  double shadow_below_db = 10.0;
  /// Above the transition, a last stage that fits the two ears together:
  /// per ear and third-octave band a mix of the channels' filters, chosen
  /// for the band spectra, each ear's broadband level and the ILD at the
  /// horizontal measurements at once (above).
  bool joint_ear_fit = true;
  /// The joint fit's weight on the horizontal ILD errors, and on each ear's
  /// broadband level error there, against the band spectra.
  double ild_weight = 1.0;
  double level_weight = 1.0;
  bool diffuse_covariance = false;
  /// Tikhonov weight relative to the normal matrix's mean diagonal.
  double regularisation = 1e-3;
  /// Taps per filter; 0: the HRTF filters' length plus their largest delay,
  /// rounded up to a power of two.
  std::size_t length = 0;
};

/// The version of what design_binaural_decoder() computes: bump it with any
/// change to its results, so filters kept on disk are designed again.
inline constexpr std::uint32_t kDecoderDesignVersion = 2;
/// Every input of a design in one line (the version, the order and each
/// field of `design`), for a cache key beside the SOFA file's hash and the
/// rate.
[[nodiscard]] std::string design_key(const DecoderDesign& design, int order);

/// The transition frequency `design` means at `order`.
[[nodiscard]] double transition_hz_for(const DecoderDesign& design, int order);

struct DecoderFilters {
  int order = 0;
  double sample_rate = 0.0;
  std::size_t length = 0;  ///< taps per filter
  std::vector<float> taps;  ///< [ear][channel][length], ACN SN3D input

  [[nodiscard]] std::size_t channels() const { return static_cast<std::size_t>((order + 1) * (order + 1)); }
  /// Ear 0 is the left.
  [[nodiscard]] std::span<const float> filter(std::size_t ear, std::size_t channel) const {
    return std::span<const float>(taps).subspan((ear * channels() + channel) * length, length);
  }

  /// The byte form: magic, format version, order, rate, length, taps
  /// (little-endian float32).
  [[nodiscard]] std::vector<std::uint8_t> serialise() const;
  /// Throws std::invalid_argument naming what does not fit (magic, version,
  /// order, rate, sizes, a tap that is not finite).
  [[nodiscard]] static DecoderFilters deserialise(std::span<const std::uint8_t> bytes);
};

/// Designs the decoder for `order` (1..kMaxOrder) from shell 0 of `set`, at
/// the set's rate. Throws std::invalid_argument for an order outside that
/// range or a set with fewer measurements than (N+1)^2.
[[nodiscard]] DecoderFilters design_binaural_decoder(const hrtf::HrtfSet& set, int order,
                                                     const DecoderDesign& design = {});

/// The quadrature weights described above, one per measurement of shell 0
/// (sum: the covered share of the sphere times 4 pi).
[[nodiscard]] std::vector<double> sphere_quadrature(const hrtf::HrtfSet& set);

}  // namespace earshot::ambisonics
