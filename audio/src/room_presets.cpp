#include "earshot/audio/room_presets.hpp"

#include <array>
#include <cmath>
#include <string>

#include "earshot/errors.hpp"

namespace earshot::audio {
namespace {

// Field order: density, diffusion, gain, gain_hf, gain_lf, decay_time_s,
// decay_hf_ratio, decay_lf_ratio, reflections_gain, reflections_delay_s,
// late_reverb_gain, late_reverb_delay_s, echo_time_s, echo_depth,
// modulation_time_s, modulation_depth, air_absorption_gain_hf,
// hf_reference_hz, lf_reference_hz, room_rolloff_factor, decay_hf_limit.
// Copied from shared/reference/efx_presets.tsv.
const std::array<RoomPreset, 29> kPresets{{
    {"generic", "EFX", {1.0, 1.0, 0.3162, 0.8913, 1.0, 1.49, 0.83, 1.0, 0.05, 0.007, 1.2589, 0.011, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"padded-cell", "EFX", {0.1715, 1.0, 0.3162, 0.001, 1.0, 0.17, 0.1, 1.0, 0.25, 0.001, 1.2691, 0.002, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"room", "EFX", {0.4287, 1.0, 0.3162, 0.5929, 1.0, 0.4, 0.83, 1.0, 0.1503, 0.002, 1.0629, 0.003, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"bathroom", "EFX", {0.1715, 1.0, 0.3162, 0.2512, 1.0, 1.49, 0.54, 1.0, 0.6531, 0.007, 3.2734, 0.011, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"living-room", "EFX", {0.9766, 1.0, 0.3162, 0.001, 1.0, 0.5, 0.1, 1.0, 0.2051, 0.003, 0.2805, 0.004, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"stone-room", "EFX", {1.0, 1.0, 0.3162, 0.7079, 1.0, 2.31, 0.64, 1.0, 0.4411, 0.012, 1.1003, 0.017, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"auditorium", "EFX", {1.0, 1.0, 0.3162, 0.5781, 1.0, 4.32, 0.59, 1.0, 0.4032, 0.02, 0.717, 0.03, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"concert-hall", "EFX", {1.0, 1.0, 0.3162, 0.5623, 1.0, 3.92, 0.7, 1.0, 0.2427, 0.02, 0.9977, 0.029, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"cave", "EFX", {1.0, 1.0, 0.3162, 1.0, 1.0, 2.91, 1.3, 1.0, 0.5, 0.015, 0.7063, 0.022, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, false}},
    {"arena", "EFX", {1.0, 1.0, 0.3162, 0.4477, 1.0, 7.24, 0.33, 1.0, 0.2612, 0.02, 1.0186, 0.03, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"hangar", "EFX", {1.0, 1.0, 0.3162, 0.3162, 1.0, 10.05, 0.23, 1.0, 0.5, 0.02, 1.256, 0.03, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"carpeted-hallway", "EFX", {0.4287, 1.0, 0.3162, 0.01, 1.0, 0.3, 0.1, 1.0, 0.1215, 0.002, 0.1531, 0.03, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"hallway", "EFX", {0.3645, 1.0, 0.3162, 0.7079, 1.0, 1.49, 0.59, 1.0, 0.2458, 0.007, 1.6615, 0.011, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"stone-corridor", "EFX", {1.0, 1.0, 0.3162, 0.7612, 1.0, 2.7, 0.79, 1.0, 0.2472, 0.013, 1.5758, 0.02, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"alley", "EFX", {1.0, 0.3, 0.3162, 0.7328, 1.0, 1.49, 0.86, 1.0, 0.25, 0.007, 0.9954, 0.011, 0.125, 0.95, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"forest", "EFX", {1.0, 0.3, 0.3162, 0.0224, 1.0, 1.49, 0.54, 1.0, 0.0525, 0.162, 0.7682, 0.088, 0.125, 1.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"city", "EFX", {1.0, 0.5, 0.3162, 0.3981, 1.0, 1.49, 0.67, 1.0, 0.073, 0.007, 0.1427, 0.011, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"mountains", "EFX", {1.0, 0.27, 0.3162, 0.0562, 1.0, 1.49, 0.21, 1.0, 0.0407, 0.3, 0.1919, 0.1, 0.25, 1.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, false}},
    {"quarry", "EFX", {1.0, 1.0, 0.3162, 0.3162, 1.0, 1.49, 0.83, 1.0, 0.0, 0.061, 1.7783, 0.025, 0.125, 0.7, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"plain", "EFX", {1.0, 0.21, 0.3162, 0.1, 1.0, 1.49, 0.5, 1.0, 0.0585, 0.179, 0.1089, 0.1, 0.25, 1.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"parking-lot", "EFX", {1.0, 1.0, 0.3162, 1.0, 1.0, 1.65, 1.5, 1.0, 0.2082, 0.008, 0.2652, 0.012, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, false}},
    {"sewer-pipe", "EFX", {0.3071, 0.8, 0.3162, 0.3162, 1.0, 2.81, 0.14, 1.0, 1.6387, 0.014, 3.2471, 0.021, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"underwater", "EFX", {0.3645, 1.0, 0.3162, 0.01, 1.0, 1.49, 0.1, 1.0, 0.5963, 0.007, 7.0795, 0.011, 0.25, 0.0, 1.18, 0.348, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"small-room", "I3DL2", {1.0, 1.0, 0.3162, 0.5012, 1.0, 1.1, 0.83, 1.0, 0.631, 0.005, 1.7783, 0.01, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"medium-room", "I3DL2", {1.0, 1.0, 0.3162, 0.5012, 1.0, 1.3, 0.83, 1.0, 0.3162, 0.01, 0.7943, 0.02, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"large-room", "I3DL2", {1.0, 1.0, 0.3162, 0.5012, 1.0, 1.5, 0.83, 1.0, 0.1585, 0.02, 0.3162, 0.04, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"medium-hall", "I3DL2", {1.0, 1.0, 0.3162, 0.5012, 1.0, 1.8, 0.7, 1.0, 0.2239, 0.015, 0.3981, 0.03, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"large-hall", "I3DL2", {1.0, 1.0, 0.3162, 0.5012, 1.0, 1.8, 0.7, 1.0, 0.1, 0.03, 0.1995, 0.06, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
    {"plate", "I3DL2", {0.75, 1.0, 0.3162, 0.7943, 1.0, 1.3, 0.9, 1.0, 1.0, 0.002, 1.0, 0.01, 0.25, 0.0, 0.25, 0.0, 0.9943, 5000.0, 250.0, 0.0, true}},
}};

struct Range {
  const char* field;
  double RoomParams::*member;
  double lo, hi;
};

constexpr std::array<Range, 22> kRanges{{
    {"density", &RoomParams::density, 0.0, 1.0},
    {"diffusion", &RoomParams::diffusion, 0.0, 1.0},
    {"gain", &RoomParams::gain, 0.0, 1.0},
    {"gain_hf", &RoomParams::gain_hf, 0.0, 1.0},
    {"gain_lf", &RoomParams::gain_lf, 0.0, 1.0},
    {"decay_time_s", &RoomParams::decay_time_s, 0.1, 20.0},
    {"decay_hf_ratio", &RoomParams::decay_hf_ratio, 0.1, 2.0},
    {"decay_lf_ratio", &RoomParams::decay_lf_ratio, 0.1, 2.0},
    {"reflections_gain", &RoomParams::reflections_gain, 0.0, 3.16},
    {"reflections_delay_s", &RoomParams::reflections_delay_s, 0.0, 0.3},
    {"late_reverb_gain", &RoomParams::late_reverb_gain, 0.0, 10.0},
    {"late_reverb_delay_s", &RoomParams::late_reverb_delay_s, 0.0, 0.1},
    {"echo_time_s", &RoomParams::echo_time_s, 0.075, 0.25},
    {"echo_depth", &RoomParams::echo_depth, 0.0, 1.0},
    {"modulation_time_s", &RoomParams::modulation_time_s, 0.04, 4.0},
    {"modulation_depth", &RoomParams::modulation_depth, 0.0, 1.0},
    {"air_absorption_gain_hf", &RoomParams::air_absorption_gain_hf, 0.892, 1.0},
    {"hf_reference_hz", &RoomParams::hf_reference_hz, 1000.0, 20000.0},
    {"lf_reference_hz", &RoomParams::lf_reference_hz, 20.0, 1000.0},
    {"room_rolloff_factor", &RoomParams::room_rolloff_factor, 0.0, 10.0},
    {"wet_db", &RoomParams::wet_db, -1e300, 20.0},
    {"dry_db", &RoomParams::dry_db, -1e300, 20.0},
}};

std::string number(double v) {
  std::string s = std::to_string(v);
  s.erase(s.find_last_not_of('0') + 1);
  if (!s.empty() && s.back() == '.') s.pop_back();
  return s;
}

}  // namespace

std::span<const RoomPreset> room_presets() { return kPresets; }

std::string room_preset_names() {
  std::string out;
  for (const auto& p : kPresets) {
    if (!out.empty()) out += ", ";
    out += p.name;
  }
  return out;
}

const RoomParams* find_room_preset(std::string_view name) {
  if (name == "default") name = "generic";  // the thesis lists both; EFX's default is generic
  if (name == "musical-plate") name = "plate";
  for (const auto& p : kPresets)
    if (p.name == name) return &p.params;
  return nullptr;
}

const RoomParams& room_preset(std::string_view name) {
  if (const RoomParams* p = find_room_preset(name)) return *p;
  throw InputError("unknown room preset '" + std::string(name) + "' (available: " + room_preset_names() + ")");
}

void validate(const RoomParams& p) {
  for (const auto& r : kRanges) {
    const double v = p.*r.member;
    // -inf dB is a fine wet/dry level (silence); NaN never is.
    const bool db_field = r.lo < -1e299;
    if (std::isnan(v) || (!db_field && !std::isfinite(v)) || v < r.lo || v > r.hi) {
      const std::string range = db_field ? "at most " + number(r.hi) : number(r.lo) + " to " + number(r.hi);
      throw InputError::at("room", 0, r.field, "must be " + range + ", got " + (std::isnan(v) ? "NaN" : number(v)));
    }
  }
}

}  // namespace earshot::audio
