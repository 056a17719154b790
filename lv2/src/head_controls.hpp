// The IEM SceneRotator's invert switches and rotation order, as the panner
// applies them to the head it turns (the offsets and the tracker together,
// as SceneRotator applies its switches to its yaw, pitch and roll whatever
// set them): the head's yaw, pitch and roll (Earshot's: yaw + left, pitch +
// up, roll + right shoulder, taken yaw first) with the chosen ones negated,
// put back together in the chosen order. With no switch set and the default
// order the head is returned as it is. Pure, real-time safe (arithmetic only).
#pragma once

#include "earshot/geometry.hpp"

namespace earshot::lv2 {

struct HeadControls {
  bool invert_yaw = false, invert_pitch = false, invert_roll = false;
  /// 0: yaw, then pitch, then roll (intrinsic: Earshot's own order);
  /// 1: roll, then pitch, then yaw (what a tracker of the other order means).
  int order = 0;

  [[nodiscard]] bool identity() const { return !invert_yaw && !invert_pitch && !invert_roll && order == 0; }
};

/// The head orientation with the switches and the order applied.
[[nodiscard]] inline Quat adjust_head(const Quat& head, const HeadControls& c) {
  if (c.identity()) return head;
  const YawPitchRoll a = ypr_from_quat(head);
  const double yaw = c.invert_yaw ? -a.yaw : a.yaw, pitch = c.invert_pitch ? -a.pitch : a.pitch,
               roll = c.invert_roll ? -a.roll : a.roll;
  if (c.order == 0) return quat_from_ypr(yaw, pitch, roll);
  // Roll first: the same three rotations composed the other way round.
  const Quat y = quat_from_ypr(yaw, 0, 0), p = quat_from_ypr(0, pitch, 0), r = quat_from_ypr(0, 0, roll);
  return multiply(multiply(r, p), y);
}

}  // namespace earshot::lv2
