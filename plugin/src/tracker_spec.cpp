#include "tracker_spec.hpp"

#include <charconv>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/tracker/led_model.hpp"
#include "earshot/tracker/opentrack_packet.hpp"
#include "earshot/tracker/osc_pose.hpp"
#include "earshot/tracker/sim_source.hpp"
#include "earshot/tracker/udp_pose_source.hpp"
#include "earshot/tracker/wiimote_source.hpp"

namespace earshot::plugin {
namespace {

std::uint16_t port(std::string_view spec, std::size_t colon, std::uint16_t fallback) {
  if (colon == std::string_view::npos) return fallback;
  const std::string_view p = spec.substr(colon + 1);
  unsigned v = 0;
  const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), v);
  if (p.empty() || ec != std::errc{} || end != p.data() + p.size() || v < 1 || v > 65535)
    throw InputError::at("tracker", 0, "", "bad UDP port in '" + std::string(spec) + "'");
  return static_cast<std::uint16_t>(v);
}

}  // namespace

std::unique_ptr<tracker::FrameSource> make_frame_source(std::string_view spec) {
  using namespace earshot::tracker;
  const std::size_t colon = spec.find(':');
  const std::string_view kind = spec.substr(0, colon);
  const bool bare = colon == std::string_view::npos;
  if (kind == "wiimote" && bare) {
    WiimoteOptions opt;
    opt.wait_for_remote = true;  // the host plays on and shows how to pair one (esGetTrackerState)
    return std::make_unique<WiimoteSource>(make_hidapi_transport(), opt);
  }
  if (kind == "sim" && bare) return std::make_unique<SimSource>(Camera::with_focal(1280.0), LedModel::thesis(), SimSourceConfig{});
  if (kind == "replay" && !bare) return std::make_unique<ReplaySource>(std::string(spec.substr(colon + 1)), Pacing::real_time);
  if (kind == "opentrack")
    return std::make_unique<UdpPoseSource>("opentrack", port(spec, colon, kOpentrackDefaultPort), true, decode_opentrack);
  if (kind == "osc") return std::make_unique<UdpPoseSource>("osc", port(spec, colon, kOscDefaultPort), true, decode_osc);
  throw InputError::at("tracker", 0, "",
                       "unknown source '" + std::string(spec) + "' (wiimote, sim, replay:FILE, opentrack[:PORT], osc[:PORT])");
}

}  // namespace earshot::plugin
