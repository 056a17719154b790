// A live tracker source from its spec: "wiimote", "sim", "replay:DOTS.csv",
// "opentrack[:PORT]", "osc[:PORT]" (the same names as `earshot track live`).
#pragma once

#include <memory>
#include <string_view>

#include "earshot/tracker/frame_source.hpp"

namespace earshot::plugin {

/// Throws earshot::InputError for an unknown spec or a bad port, and
/// whatever the source's constructor throws (port in use, unreadable file).
/// "wiimote" waits for a remote (WiimoteOptions::wait_for_remote): none found
/// is a state (ES_TRACKER_SEARCHING with how to pair one), not an error.
[[nodiscard]] std::unique_ptr<tracker::FrameSource> make_frame_source(std::string_view spec);

}  // namespace earshot::plugin
