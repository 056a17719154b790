// Fuzzes the pose-output spec parser (tracker/send/send_spec.hpp), single
// specs and ';' lists, as they come from the command line, the C API's
// tracker options and an LV2 host's saved state: any text parses into specs
// within range or throws InputError naming the spec; a parsed list prints
// back to text that parses to the same specs.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "earshot/errors.hpp"
#include "earshot/tracker/send/send_spec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace t = earshot::tracker;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto list = t::parse_send_list(text, "send");
    for (const t::SendSpec& s : list) {
      if (s.port == 0 || s.host.empty() || !std::isfinite(s.rate_hz) || s.rate_hz < 1.0 || s.rate_hz > 1000.0) std::abort();
      if (s.kind == t::SendSpec::Kind::opentrack && s.format != t::SendSpec::Format::earshot) std::abort();
    }
    if (t::parse_send_list(t::send_list_text(list), "send") != list) std::abort();
  } catch (const earshot::InputError& e) {
    if (std::string_view(e.what()).empty()) std::abort();
  }
  try {
    (void)t::parse_send_spec(text, "--send");
  } catch (const earshot::InputError&) {
  }
  return 0;
}
