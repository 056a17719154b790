// What the preload shim gives OpenAL for one context: the program's own
// listener (p, P) with the tracked head placed on it as the head will be
// when the next mix is heard (earshot/head/head_reader.hpp: heard, compose).
// Pure, so tests check it without OpenAL.
#pragma once

#include <cstddef>

#include "earshot/geometry.hpp"
#include "earshot/head/head_reader.hpp"

namespace earshot::preload {

struct ShimListener {
  float position[3]{};     ///< AL_POSITION: p + P h
  float orientation[6]{};  ///< AL_ORIENTATION: "at" then "up" of P H
  HeadPose head;           ///< the tracked head as heard (relative to the program's listener)
};

/// `program`: the listener the program set (position, orientation);
/// `tracked`: the newest published head pose; `lead_s`: the device's
/// latency (openal_latency.hpp); `now_s`: steady-clock seconds.
[[nodiscard]] inline ShimListener shim_listener(const HeadPose& program, const HeadPose& tracked, double lead_s,
                                                double now_s) {
  ShimListener out;
  out.head = head::heard(tracked, {.predict = true, .lead_s = lead_s}, now_s);
  const HeadPose l = head::compose(program, out.head);
  const Vec3 at = rotate(l.orientation, {0, 0, -1}), up = rotate(l.orientation, {0, 1, 0});
  for (std::size_t i = 0; i < 3; ++i) {
    out.position[i] = static_cast<float>(l.position[i]);
    out.orientation[i] = static_cast<float>(at[i]);
    out.orientation[3 + i] = static_cast<float>(up[i]);
  }
  return out;
}

}  // namespace earshot::preload
