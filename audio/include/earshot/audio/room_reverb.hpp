// A room's reverb, as the renderer's send bus needs it: mono send in, stereo
// return out, built from the preset's parameters (room_presets.hpp):
//
//   in -> input filter (gain_hf at hf_reference_hz)
//      -> early reflections, from reflections_delay_s, level reflections_gain
//      -> pre-delay to reflections_delay_s + late_reverb_delay_s
//         -> late reverb (FDN or Schroeder), level late_reverb_gain
//   out = gain * wet * (reflections + late) + dry * in (both ears)
//
// The late reverb's own latency (its shortest line) is taken off the
// pre-delay, so its first echoes come at the late reverb delay.
// Not rendered yet: gain_lf, decay_lf_ratio, echo and modulation, air
// absorption and room rolloff (distance effects of the source, not the room).
// Allocates at construction only; update() and process() never allocate.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "earshot/audio/biquad.hpp"
#include "earshot/audio/early_reflections.hpp"
#include "earshot/audio/reverb_fdn.hpp"
#include "earshot/audio/reverb_schroeder.hpp"
#include "earshot/audio/room_presets.hpp"

namespace earshot::audio {

enum class LateReverbType { fdn, schroeder };

/// "fdn" or "schroeder"; throws earshot::InputError naming anything else.
[[nodiscard]] LateReverbType late_reverb_type(std::string_view name);

class RoomReverb {
 public:
  /// Validates `p` (throws earshot::InputError) and allocates everything.
  RoomReverb(double sample_rate, std::size_t block, const RoomParams& p, LateReverbType type = LateReverbType::fdn);

  /// New parameters (validated: throws earshot::InputError, keeping the old
  /// ones); never allocates. They apply from the next process().
  void update(const RoomParams& p);
  /// in: block() samples (or fewer); writes as many to out_left / out_right.
  void process(std::span<const float> in, std::span<float> out_left, std::span<float> out_right);
  void reset();

  [[nodiscard]] std::size_t block() const { return block_; }
  [[nodiscard]] const RoomParams& params() const { return params_; }
  [[nodiscard]] LateReverbType late_type() const { return type_; }

 private:
  double rate_;
  std::size_t block_;
  LateReverbType type_;
  RoomParams params_;
  std::array<Biquad, 2> input_filter_;
  EarlyReflections early_;
  std::optional<ReverbFdn> fdn_;
  std::optional<ReverbSchroeder> schroeder_;
  std::vector<float> filtered_, predelay_ring_, late_in_, late_l_, late_r_;
  std::size_t predelay_mask_ = 0, predelay_ = 0, write_ = 0;
  float wet_ = 1.0f, dry_ = 0.0f;
};

}  // namespace earshot::audio
