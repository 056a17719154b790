// Room presets: the parameters of a room's reverb, by name.
//
// The fields are OpenAL's EFX reverb parameters (gains linear, times in
// seconds), so a preset can be handed to OpenAL Soft unchanged for
// comparison. The thesis's Table 1 ("late reverberation user parameters")
// maps onto them:
//   wet and dry levels        -> wet_db, dry_db (a send bus: dry silent, wet 0 dB)
//   early reflections delay   -> reflections_delay_s (direct sound to first reflection)
//   reverberation delay       -> late_reverb_delay_s (first reflection to late reverb)
//   reverberation decay time  -> decay_time_s (RT60 at mid frequencies)
//   frequency decay ratio     -> decay_hf_ratio (RT60 at hf_reference_hz / decay_time_s)
//   reverberation level       -> late_reverb_gain (relative to reflections_gain)
//   room type                 -> the preset name
// Figures: OpenAL Soft's efx-presets.h (23 "EFX" rows) and the six I3DL2
// "musical" presets, converted (see docs/ARCHITECTURE.md, "Reverbs and rooms").
// Names are lower-case with hyphens, e.g. "generic", "concert-hall".
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace earshot::audio {

struct RoomParams {
  double density = 1.0;             ///< [0, 1] modal density: scales the delay lines
  double diffusion = 1.0;           ///< [0, 1] echo density of the late reverb
  double gain = 0.3162;             ///< [0, 1] overall level of the reverb
  double gain_hf = 0.8913;          ///< [0, 1] level at hf_reference_hz (input low-pass)
  double gain_lf = 1.0;             ///< [0, 1] level at lf_reference_hz (not rendered yet)
  double decay_time_s = 1.49;       ///< [0.1, 20] RT60 at mid frequencies
  double decay_hf_ratio = 0.83;     ///< [0.1, 2] RT60 at hf_reference_hz / decay_time_s
  double decay_lf_ratio = 1.0;      ///< [0.1, 2] RT60 at lf_reference_hz / decay_time_s
  double reflections_gain = 0.05;   ///< [0, 3.16] early reflections level
  double reflections_delay_s = 0.007;  ///< [0, 0.3] direct sound to first reflection
  double late_reverb_gain = 1.2589;    ///< [0, 10] late reverb level
  double late_reverb_delay_s = 0.011;  ///< [0, 0.1] first reflection to late reverb
  double echo_time_s = 0.25;        ///< [0.075, 0.25] (EFX field, not rendered)
  double echo_depth = 0.0;          ///< [0, 1] (EFX field, not rendered)
  double modulation_time_s = 0.25;  ///< [0.04, 4] (EFX field, not rendered)
  double modulation_depth = 0.0;    ///< [0, 1] (EFX field, not rendered)
  double air_absorption_gain_hf = 0.9943;  ///< [0.892, 1] (EFX field, not rendered)
  double hf_reference_hz = 5000.0;  ///< [1000, 20000]
  double lf_reference_hz = 250.0;   ///< [20, 1000]
  double room_rolloff_factor = 0.0;  ///< [0, 10] (EFX field, not rendered)
  bool decay_hf_limit = true;       ///< (EFX field, not rendered)
  double wet_db = 0.0;              ///< [-120, 20] reverb out; <= -120 is silence
  double dry_db = -120.0;           ///< [-120, 20] input passed through; <= -120 is silence
};

struct RoomPreset {
  std::string_view name;
  std::string_view source;  ///< "EFX" or "I3DL2"
  RoomParams params;
};

/// Every preset, in the order of the reference table (29 rooms).
[[nodiscard]] std::span<const RoomPreset> room_presets();

/// The preset called `name` ("default" is "generic", "musical-plate" is
/// "plate"), or nullptr when there is none.
[[nodiscard]] const RoomParams* find_room_preset(std::string_view name);

/// The preset called `name`, as find_room_preset. Throws
/// earshot::InputError naming it and listing the valid names.
[[nodiscard]] const RoomParams& room_preset(std::string_view name);

/// "generic, padded-cell, ..." for messages and --help.
[[nodiscard]] std::string room_preset_names();

/// Throws earshot::InputError naming the first field outside its range
/// (ranges as documented above; non-finite values are out of range).
void validate(const RoomParams& p);

}  // namespace earshot::audio
