// Faults injected into a stream of camera frames, to show the live tracker
// survives what a real camera does: dots vanish and come back, two dots swap
// camera slots, a stray reflection takes an LED's place, a burst of garbage
// (NaN, outside the image), and the source going silent.
#pragma once

#include <span>

#include "earshot/tracker/core/dots_csv.hpp"

namespace earshot::tracker {

struct Fault {
  enum class Kind {
    vanish,   ///< every dot gone (slots empty)
    drop_one, ///< the dot in slot `slot` gone
    swap,     ///< slots `slot` and `other` exchange their dots
    stray,    ///< the dot in slot `slot` replaced by a reflection at `where`
    garbage,  ///< NaN and out-of-image coordinates in every slot
    silence,  ///< no frame at all: the source reports timeouts
  };
  Kind kind = Kind::vanish;
  long first = 0;   ///< first frame index affected
  long count = 1;   ///< frames affected
  int slot = 0, other = 1;
  Vec2 where{100.0, 100.0};

  [[nodiscard]] bool covers(long frame) const { return frame >= first && frame < first + count; }
};

/// Applies every fault covering `frame` to `f`, in order.
void apply_faults(DotFrame& f, long frame, std::span<const Fault> faults);

/// True when a silence fault covers `frame`.
[[nodiscard]] bool silenced(long frame, std::span<const Fault> faults);

}  // namespace earshot::tracker
