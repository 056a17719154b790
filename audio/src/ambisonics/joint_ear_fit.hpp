// The last stage of the binaural decoder design: the two ears fitted
// together above the transition (DecoderDesign::joint_ear_fit). Internal to
// binaural_decoder_design.cpp; its own file because it is an optimisation
// problem of its own (a cost, its gradient, L-BFGS).
#pragma once

#include <Eigen/Dense>
#include <cstddef>
#include <vector>

#include "earshot/audio/ambisonics/binaural_decoder_design.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace earshot::ambisonics::design_detail {

/// Shadow weighting and the joint fit: a direction's power counts at least
/// this share of the band's mean (-30 dB), so a deep notch does not take all
/// the weight.
inline constexpr double kPowerFloor = 1e-3;

/// Mixes, per ear and band of `bands` (bin indices: each band's first bin,
/// then one past the last), the channels' filters `D` (C x bins per ear)
/// so the two ears' band levels, broadband levels and ILD at the horizontal
/// measurements fit the measured spectra `H` (Q x bins per ear) together.
/// `Y`: the real SH matrix at the measurements (Q x C); `w`: their
/// quadrature weights. Each bin's phase stays D's.
void fit_ears_jointly(const hrtf::HrtfSet& set, int order, const DecoderDesign& design, const Eigen::MatrixXd& Y,
                      const std::vector<double>& w, const Eigen::MatrixXcd (&H)[2], Eigen::MatrixXcd (&D)[2],
                      const std::vector<std::size_t>& bands);

}  // namespace earshot::ambisonics::design_detail
