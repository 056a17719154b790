// How long until what an OpenAL device mixes next is heard: what a head
// pose applied to an OpenAL listener now is predicted ahead by (the OpenAL
// bridge and the preload shim). Header only: both link OpenAL themselves.
#pragma once

#include <AL/alc.h>
#include <AL/alext.h>

namespace earshot::openal {

/// Seconds: ALC_SOFT_device_clock's ALC_DEVICE_LATENCY_SOFT where the device
/// has it (OpenAL Soft: what its backend holds), plus one update period
/// (1 / ALC_REFRESH: a pose set now is mixed at the next update); 0 without
/// a device. Calls into OpenAL (it may lock the device): never on an audio
/// callback.
inline double output_latency_s(ALCdevice* device) {
  if (!device) return 0.0;
  double latency = 0.0;
  if (alcIsExtensionPresent(device, "ALC_SOFT_device_clock")) {
    const auto get = reinterpret_cast<LPALCGETINTEGER64VSOFT>(alcGetProcAddress(device, "alcGetInteger64vSOFT"));
    ALCint64SOFT ns = 0;
    if (get) get(device, ALC_DEVICE_LATENCY_SOFT, 1, &ns);
    if (ns > 0 && ns < 1'000'000'000) latency = static_cast<double>(ns) * 1e-9;
  }
  ALCint refresh = 0;
  alcGetIntegerv(device, ALC_REFRESH, 1, &refresh);
  if (refresh > 0 && refresh < 100000) latency += 1.0 / refresh;
  return latency;
}

}  // namespace earshot::openal
