#include "earshot/webcam/webcam_spec.hpp"

#include <charconv>
#include <cmath>
#include <set>

#include "earshot/errors.hpp"

namespace earshot::webcam {
namespace {

/// "FIELD: source 'SPEC': WHY", as the rest of the source spec says it.
InputError spec_error(std::string_view field, std::string_view spec, const std::string& why) {
  return InputError::at(field, 0, "", "source '" + std::string(spec) + "': " + why);
}

template <typename T>
bool parse_number(std::string_view text, T& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return !text.empty() && ec == std::errc{} && end == text.data() + text.size();
}

}  // namespace

WebcamSpec parse_webcam_spec(std::string_view spec, std::string_view field, std::string_view rest) {
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
        throw fail("bad size_mm '" + v + "' (mm, 5-1000: the side of the square the detector finds, the outside of "
                   "tag36h11's black border, the inside of tagStandard41h12's black ring)");
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

bool WebcamSpec::is_file() const {
  return device.size() > 4 && device.compare(device.size() - 4, 4, ".y4m") == 0;
}

}  // namespace earshot::webcam
