#include "earshot/tracker/source_spec.hpp"

#include <charconv>
#include <cmath>
#include <set>

#include "earshot/errors.hpp"
#include "earshot/tracker/opentrack_packet.hpp"
#include "earshot/tracker/osc_pose.hpp"
#include "earshot/tracker/udp_pose_source.hpp"
#include "earshot/tracker/udp_socket.hpp"
#include "earshot/tracker/webcam_source.hpp"
#include "earshot/tracker/wiimote_source.hpp"

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

template <typename T>
bool parse_number(std::string_view text, T& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return !text.empty() && ec == std::errc{} && end == text.data() + text.size();
}

/// webcam[:DEVICE][,KEY=VALUE]...; `rest` is what follows "webcam".
WebcamSpec parse_webcam(std::string_view spec, std::string_view field, std::string_view rest) {
  WebcamSpec w;
  const auto fail = [&](const std::string& why) { return spec_error(field, spec, why); };
  const std::size_t comma = rest.find(',');
  std::string_view device = rest.substr(0, comma);
  std::string_view options = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
  if (!device.empty()) {
    if (device.front() != ':') throw fail("expected ':DEVICE' or ',OPTION=VALUE' after 'webcam'");
    device.remove_prefix(1);
    if (device.empty()) throw fail("empty device after 'webcam:' (/dev/videoN, N or a .y4m file)");
    if (unsigned n = 0; parse_number(device, n)) w.device = "/dev/video" + std::to_string(n);
    else if (device.front() >= '0' && device.front() <= '9' && device.find('.') == std::string_view::npos)
      throw fail("bad camera number '" + std::string(device) + "' (0, 1, ...)");
    else w.device = std::string(device);
  }
  std::set<std::string, std::less<>> seen;
  bool tag_option = false;
  while (comma != std::string_view::npos) {
    const std::size_t next = options.find(',');
    const std::string_view item = options.substr(0, next);
    options = next == std::string_view::npos ? std::string_view() : options.substr(next + 1);
    const std::size_t eq = item.find('=');
    const std::string_view key = item.substr(0, eq);
    if (eq == std::string_view::npos || key.empty())
      throw fail("expected OPTION=VALUE, got '" + std::string(item) + "'");
    const std::string_view value = item.substr(eq + 1);
    const std::string k(key), v(value);
    if (!seen.insert(k).second) throw fail("webcam option '" + k + "' given twice");
    if (value.empty()) throw fail("webcam option '" + k + "' has no value");
    if (key == "beacon") {
      if (value == "leds") w.beacon = WebcamSpec::Beacon::leds;
      else if (value == "apriltag") w.beacon = WebcamSpec::Beacon::apriltag;
      else throw fail("bad beacon '" + v + "' (leds or apriltag)");
    } else if (key == "size_mm") {
      if (!parse_number(value, w.size_mm) || !std::isfinite(w.size_mm) || w.size_mm < 5.0 || w.size_mm > 1000.0)
        throw fail("bad size_mm '" + v + "' (the tag's black square in mm, 5-1000)");
      tag_option = true;
    } else if (key == "family") {
      w.family = v;
      tag_option = true;
    } else if (key == "id") {
      if (!parse_number(value, w.id) || w.id < 0 || w.id > 65535) throw fail("bad tag id '" + v + "' (0-65535)");
      tag_option = true;
    } else if (key == "decimate") {
      if (!parse_number(value, w.decimate) || !std::isfinite(w.decimate) || w.decimate < 1.0 || w.decimate > 8.0)
        throw fail("bad decimate '" + v + "' (the tag search's image reduction, 1-8)");
      tag_option = true;
    } else if (key == "focal") {
      double f = 0.0;
      if (!parse_number(value, f) || !std::isfinite(f) || f < 10.0 || f > 100000.0)
        throw fail("bad focal '" + v + "' (the focal length in pixels, 10-100000)");
      w.focal_px = f;
    } else if (key == "calib") {
      w.calib = v;
    } else if (key == "resolution") {
      const std::size_t x = value.find('x');
      if (x == std::string_view::npos || !parse_number(value.substr(0, x), w.max_width) ||
          !parse_number(value.substr(x + 1), w.max_height) || w.max_width < 16 || w.max_height < 16 ||
          w.max_width > 8192 || w.max_height > 8192)
        throw fail("bad resolution '" + v + "' (WIDTHxHEIGHT, e.g. 640x480; 16-8192 each)");
    } else if (key == "fps") {
      if (!parse_number(value, w.max_fps) || w.max_fps < 1 || w.max_fps > 1000)
        throw fail("bad fps '" + v + "' (frames per second, 1-1000)");
    } else {
      throw fail("unknown webcam option '" + k + "' (beacon, size_mm, family, id, decimate, focal, calib, resolution, fps)");
    }
    if (next == std::string_view::npos) break;
  }
  if (tag_option && w.beacon != WebcamSpec::Beacon::apriltag)
    throw fail("size_mm, family, id and decimate are for beacon=apriltag (the LED beacon's shape comes from --model)");
  return w;
}

}  // namespace

bool WebcamSpec::is_file() const {
  return device.size() > 4 && device.compare(device.size() - 4, 4, ".y4m") == 0;
}

SourceSpec parse_source_spec(std::string_view spec, std::string_view field) {
  using Kind = SourceSpec::Kind;
  if (spec.starts_with("webcam") && (spec.size() == 6 || spec[6] == ':' || spec[6] == ',')) {
    SourceSpec s;
    s.kind = Kind::webcam;
    s.webcam = parse_webcam(spec, field, spec.substr(6));
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
    case SourceSpec::Kind::webcam: return make_webcam_source(spec.webcam, o);
  }
  throw std::logic_error("make_frame_source: unknown source kind");
}

}  // namespace earshot::tracker
