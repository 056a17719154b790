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
//   of lateral sources is too complex and the fit loses level, mostly at
//   the far ear's expense.
// - magls (Schoerkhuber, Zaunschirm and Hoeldrich 2018, "Binaural
//   rendering of Ambisonic signals via magnitude least squares"): the same
//   LS below `transition_hz`; above it, only the magnitudes are fitted,
//   with each direction's phase taken from the previous frequency bin's
//   decoder (so the phase runs on smoothly and is as simple as the order
//   allows).
// Options on top:
// - diffuse_covariance (Zaunschirm, Schoerkhuber and Hoeldrich 2018, JASA
//   143(6)): per bin, a 2x2 mix of the two ears' filters so that a diffuse
//   field (incoherent waves from everywhere) has the HRTF set's ear powers
//   and interaural coherence. Above the transition only.
// - band_energy_iterations: after the MagLS fit, each direction's and ear's
//   magnitude target in each third-octave band is rescaled by what the
//   decoder reproduced there, and the fit run again, that many times. The
//   order-N fit smooths the magnitude over direction and overestimates the
//   far ear where the head shadow's notches are; the rescaled targets pull
//   each band's level back to the measured one, so the rendered broadband
//   ILD follows the HRTF's (tests/bench/ambi_cues.cpp; docs/AMBISONICS.md).
//
// Quadrature: each measurement weighs its spherical Voronoi cell, estimated
// by assigning 2^15 near-uniform (Fibonacci) points on the sphere to their
// nearest measurement; a point farther than twice the grid's median
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
  /// order, at most 2 kHz... see transition_hz_for().
  double transition_hz = 0.0;
  bool diffuse_covariance = false;
  int band_energy_iterations = 0;
  /// Tikhonov weight relative to the normal matrix's mean diagonal.
  double regularisation = 1e-3;
  /// Taps per filter; 0: the HRTF filters' length plus their largest delay,
  /// rounded up to a power of two.
  std::size_t length = 0;
};

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
