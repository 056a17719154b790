// One partitioned convolver per measured HRTF direction and ear, shared by
// every source: a source pans its (already delayed) ear signals into the
// three measurements its direction blends, with the blend's weights, and
// each measurement's filter then runs once for everyone who uses it.
//
// Convolution is linear, so this is exactly the per-source blend
//   y = sum_s (g_s sum_k w_sk h_k) * x_s  =  sum_k h_k * (sum_s g_s w_sk x_s)
// with the filters' onsets removed (the ITD stays in each source's delay
// lines), so nothing combs. What it buys: a source costs a few scaled adds
// per block, not FFTs and multiply-adds over its own filter spectra, and
// holds no filter or spectrum history of its own; the convolution cost
// grows with the number of directions in use (at most the measurements),
// not with the number of sources. A moving source needs no filter
// crossfade: its weights ramp across the block, so each input sample goes
// through the blend of its own moment (a crossfade on the input side).
//
// Each (measurement, ear) lane is uniformly partitioned overlap-save (block
// B, FFT 2B) over HrtfSpectra's planar spectra, with the delay line on the
// output side: a lane's input spectrum times filter partition p is added
// into the shared accumulator of the block p blocks ahead, per ear. So a
// lane keeps no spectrum history and costs nothing once its input stops
// (its tail is already in the accumulators); each block ends with one
// inverse FFT per ear of the accumulator that is due.
//
// A DSP unit the Resonance way: everything is allocated at construction;
// add() and process() never allocate, lock or do I/O.
#pragma once

#include <complex>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "earshot/audio/aligned_vector.hpp"
#include "earshot/audio/hrtf_spectra.hpp"
#include "earshot/audio/real_fft.hpp"

namespace earshot::audio {

class DirectionBank {
 public:
  explicit DirectionBank(std::shared_ptr<const HrtfSpectra> spectra);

  [[nodiscard]] std::size_t block() const { return block_; }
  [[nodiscard]] std::size_t measurements() const { return measurements_; }

  /// A gain across one block: sample i gets c0 + c1 r + c2 r^2 with
  /// r = (i + 1) / block() (so r = 1 is the block's last sample).
  struct GainCurve {
    float c0 = 0.0f, c1 = 0.0f, c2 = 0.0f;
    /// From g0 (before the block) to g1 (its last sample), linearly.
    [[nodiscard]] static GainCurve ramp(float g0, float g1) { return {g0, g1 - g0, 0.0f}; }
  };

  /// Adds x (block() samples) into measurement m's ear (0 left, 1 right),
  /// scaled by `gain`.
  void add(std::size_t m, std::size_t ear, std::span<const float> x, GainCurve gain);

  /// Asks the CPU for the input lines of measurement m's two lanes, which
  /// an add() will soon touch: with many sources they are spread over more
  /// memory than the nearer caches hold. A hint only: changes no state.
  void prefetch(std::size_t m) const;

  /// Convolves every lane with input or a ringing tail and adds the block's
  /// binaural output into left and right (block() samples each).
  void process(std::span<float> left, std::span<float> right);

  /// Silences every lane (inputs and tails).
  void reset();

  /// Lanes (measurement x ear) that the last process() ran.
  [[nodiscard]] std::size_t lanes_run() const { return lanes_run_; }

 private:
  struct Lane {
    bool has_input = false;   // add() wrote into this block
    bool prev_input = false;  // ... and into the previous one
    bool listed = false;      // in active_
  };
  [[nodiscard]] std::size_t lane_index(std::size_t m, std::size_t ear) const { return 2 * m + ear; }

  std::shared_ptr<const HrtfSpectra> spectra_;
  std::size_t block_, parts_, stride_, measurements_;
  RealFft fft_;
  std::vector<Lane> lanes_;
  AlignedVector<float> input_;         // [lane][2B]: this block's sum and the previous block's, halves alternating
  std::size_t half_ = 1;               // the half this block adds into
  std::vector<std::uint32_t> active_;  // lanes with input this block or the last, in first-use order
  AlignedVector<float> ahead_;         // [slot][ear][planar]: output spectra of the blocks ahead
  std::vector<char> ahead_used_;       // [slot][ear]: anything added
  std::size_t now_ = 0;               // the slot of the current block
  std::size_t lanes_run_ = 0;
  AlignedVector<std::complex<float>> spectrum_;  // one FFT's output
  AlignedVector<float> planar_;                  // ... in the planar layout
  AlignedVector<float> time_;                    // 2B, an inverse FFT's output
  AlignedVector<float> r_, r2_;                  // (i + 1) / B and its square
};

}  // namespace earshot::audio
