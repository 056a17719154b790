// Fuzzes the Wii Remote input report decoder: any bytes decode to a report
// or are dropped with a reason; decoded IR dots are inside the image; every
// data report but 0x3D (extension bytes only) carries buttons.
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "earshot/tracker/sources/wiimote_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace w = earshot::tracker::wiimote;
  std::string why;
  const auto r = w::decode(std::span(data, size), &why);
  if (!r && why.empty()) std::abort();  // a dropped report always says why
  if (r)
    if (const auto* d = std::get_if<w::DataReport>(&*r)) {
      for (const auto& dot : d->ir)
        if (dot && (dot->x > 1023 || dot->y > 767)) std::abort();
      if (d->buttons.has_value() == (d->id == 0x3D)) std::abort();
    }
  (void)w::parse_accel_calibration(std::span(data, size));
  return 0;
}
