#include "earshot/tracker/sim/frame_faults.hpp"

#include <limits>
#include <utility>

namespace earshot::tracker {

void apply_faults(DotFrame& f, long frame, std::span<const Fault> faults) {
  for (const Fault& fault : faults) {
    if (!fault.covers(frame)) continue;
    const auto s = static_cast<std::size_t>(fault.slot % kSlots);
    switch (fault.kind) {
      case Fault::Kind::vanish:
        for (auto& d : f.slots) d.reset();
        break;
      case Fault::Kind::drop_one: f.slots[s].reset(); break;
      case Fault::Kind::swap: std::swap(f.slots[s], f.slots[static_cast<std::size_t>(fault.other % kSlots)]); break;
      case Fault::Kind::stray: f.slots[s] = fault.where; break;
      case Fault::Kind::garbage: {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        f.slots = {Vec2(nan, 300.0), Vec2(5000.0, -20.0), Vec2(400.0, nan),
                   Vec2(std::numeric_limits<double>::infinity(), 1.0)};
        break;
      }
      case Fault::Kind::silence: break;  // the source handles it
    }
  }
}

bool silenced(long frame, std::span<const Fault> faults) {
  for (const Fault& fault : faults)
    if (fault.kind == Fault::Kind::silence && fault.covers(frame)) return true;
  return false;
}

}  // namespace earshot::tracker
