// The Ambisonic decoders of earshot.lv2 (ambi_plugin.cpp): their URIs and
// port layout, shared by the plugin and its turtle writer (write_ttl.cpp).
//
// Plugin `urn:earshot:lv2:ambi-binaural-oN` (N = 1..5): ports 0 ..
// (N+1)^2 - 1 are the audio inputs in ACN order (ambiX, SN3D), then, from
// (N+1)^2 on, the ports below in this order.
#pragma once

#include <lv2/core/lv2.h>

#include <cstdint>

#define EARSHOT_LV2_AMBI_URI_PREFIX "urn:earshot:lv2:ambi-binaural-o"

namespace earshot::lv2::ambi {

inline constexpr int kOrders = 5;
/// atom:String: a full tracker spec (as the panner's #tracker parameter).
inline constexpr const char* kTrackerParameter = "urn:earshot:lv2:ambi-binaural#tracker";

/// Ports after the (N+1)^2 inputs, numbered from there.
enum Port : std::uint32_t {
  kOutLeft = 0,
  kOutRight,
  kControl,  // atom:Sequence of patch:Set (the tracker spec) / patch:Get (optional)
  kNotify,   // atom:Sequence out (optional)
  kTracking,
  kTrackerSource,
  kRecenter,
  kYawOffset,
  kPitchOffset,
  kRollOffset,
  kLatency,
  kHeadYaw,
  kHeadPitch,
  kHeadRoll,
  kPortsAfterInputs
};

/// The decoder of order i + 1 (i = 0..kOrders-1), else null.
const LV2_Descriptor* descriptor(std::uint32_t i);

}  // namespace earshot::lv2::ambi
