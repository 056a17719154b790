#include "earshot/tracker/live/source_spec.hpp"

#include <charconv>
#include <cmath>
#include <set>

#include "earshot/errors.hpp"
#include "earshot/tracker/sources/opentrack_packet.hpp"
#include "earshot/tracker/sources/osc_pose.hpp"
#include "earshot/tracker/sources/udp_pose_source.hpp"
#include "earshot/tracker/sources/udp_socket.hpp"
#include "earshot/webcam/webcam_source.hpp"
#include "earshot/tracker/sources/wiimote_source.hpp"

namespace earshot::tracker {
namespace {

/// "FIELD: source 'SPEC': WHY".
InputError spec_error(std::string_view field, std::string_view spec, const std::string& why) {
  return InputError::at(field, 0, "", "source '" + std::string(spec) + "': " + why);
}

std::uint16_t port_of(std::string_view spec, std::string_view field, std::optional<std::string_view> arg,
                      std::uint16_t fallback) {
  if (!arg) return fallback;
  unsigned v = 0;
  const auto [end, ec] = std::from_chars(arg->data(), arg->data() + arg->size(), v);
  if (arg->empty() || ec != std::errc{} || end != arg->data() + arg->size() || v < 1 || v > 65535)
    throw spec_error(field, spec, "bad UDP port '" + std::string(*arg) + "' (1-65535)");
  return static_cast<std::uint16_t>(v);
}

}  // namespace

SourceSpec parse_source_spec(std::string_view spec, std::string_view field) {
  using Kind = SourceSpec::Kind;
  if (spec.starts_with("webcam") && (spec.size() == 6 || spec[6] == ':' || spec[6] == ',')) {
    SourceSpec s;
    s.kind = Kind::webcam;
    s.webcam = webcam::parse_webcam_spec(spec, field, spec.substr(6));
    return s;
  }
  // KIND[:ARG][@ADDR]; replay's ARG is a file name and may hold '@'.
  const std::size_t kind_end = spec.find_first_of(":@");
  const std::string_view kind = spec.substr(0, kind_end);
  const bool listens = kind == "opentrack" || kind == "osc";
  std::string_view rest = kind_end == std::string_view::npos ? std::string_view() : spec.substr(kind_end);
  std::optional<std::string_view> listen;
  if (listens) {
    if (const std::size_t at = rest.find('@'); at != std::string_view::npos) {
      listen = rest.substr(at + 1);
      rest = rest.substr(0, at);
    }
  }
  std::optional<std::string_view> arg;
  if (!rest.empty() && rest.front() == ':') arg = rest.substr(1);
  SourceSpec s;
  if (listen) {
    s.listen = std::string(*listen);
    if (!is_ipv4_address(s.listen))
      throw spec_error(field, spec,
                       "bad listen address '" + s.listen + "' (an IPv4 address: 127.0.0.1, 0.0.0.0 for every interface, "
                       "or one interface's address)");
  }
  if (kind == "wiimote" || kind == "sim") {
    if (!rest.empty() && rest.front() == '@')
      throw spec_error(field, spec, "'" + std::string(kind) + "' takes no listen address (only opentrack and osc listen)");
    if (arg) throw spec_error(field, spec, "'" + std::string(kind) + "' takes no argument");
    s.kind = kind == "sim" ? Kind::sim : Kind::wiimote;
  } else if (kind == "replay") {
    if (!arg || arg->empty()) throw spec_error(field, spec, "replay needs a file (replay:FILE)");
    s.kind = Kind::replay;
    s.file = std::string(*arg);
  } else if (kind == "opentrack") {
    s.kind = Kind::opentrack;
    s.port = port_of(spec, field, arg, kOpentrackDefaultPort);
  } else if (kind == "osc") {
    s.kind = Kind::osc;
    s.port = port_of(spec, field, arg, kOscDefaultPort);
  } else {
    throw InputError::at(field, 0, "", "unknown source '" + std::string(spec) + "' (" + std::string(kSourceSpecs) + ")");
  }
  return s;
}

std::string with_listen_address(std::string_view spec, std::string_view address, std::string_view spec_field,
                                std::string_view listen_field) {
  const std::string addr(address);
  if (!is_ipv4_address(addr))
    throw InputError::at(listen_field, 0, "",
                         "bad listen address '" + addr + "' (an IPv4 address: 127.0.0.1, 0.0.0.0 for every interface, "
                         "or one interface's address)");
  bool pose_source = false;
  try {
    pose_source = parse_source_spec(spec, spec_field).sends_poses();
  } catch (const InputError&) {
    if (spec != "none") throw;  // the spec's own error names the spec's field
  }
  if (!pose_source)
    throw InputError::at(listen_field, 0, "", "needs a pose source (opentrack[:PORT] or osc[:PORT]); '" +
                                                  std::string(spec) + "' does not listen on the network");
  if (spec.find('@') != std::string_view::npos)
    throw InputError::at(listen_field, 0, "", "source '" + std::string(spec) + "' already names a listen address");
  return std::string(spec) + "@" + addr;
}

std::unique_ptr<FrameSource> make_frame_source(const SourceSpec& spec, const SourceOptions& o) {
  switch (spec.kind) {
    case SourceSpec::Kind::wiimote: {
      WiimoteOptions w;
      w.wait_for_remote = o.wait_for_remote;
      return std::make_unique<WiimoteSource>(make_hidapi_transport(), w);
    }
    case SourceSpec::Kind::sim: {
      SimSourceConfig c = o.sim;
      c.pacing = o.pacing;
      return std::make_unique<SimSource>(o.camera, o.model.value_or(LedModel::thesis()), c);
    }
    case SourceSpec::Kind::replay: return std::make_unique<ReplaySource>(spec.file, o.pacing);
    case SourceSpec::Kind::opentrack:
      return std::make_unique<UdpPoseSource>("opentrack", spec.port, spec.listen, decode_opentrack);
    case SourceSpec::Kind::osc:
      return std::make_unique<UdpPoseSource>("osc", spec.port, spec.listen, OscPoseDecoder::packet_decoder());
    case SourceSpec::Kind::webcam: return webcam::make_webcam_source(spec.webcam, {.pacing = o.pacing, .wait_for_device = o.wait_for_remote});
  }
  throw std::logic_error("make_frame_source: unknown source kind");
}

}  // namespace earshot::tracker
