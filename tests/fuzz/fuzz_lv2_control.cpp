// The LV2 plugin's control port: the atom sequence a host hands run().
// The first byte picks what the rest is: 0 the raw sequence body (events,
// objects, properties with any sizes), 1 a patch:Set of the SOFA path, 2 a
// patch:Set of the tracker spec, 3 a patch:Get. No worker is offered, so a
// path or spec is only parsed and stored, never opened.
#include <algorithm>
#include <array>
#include <cstdint>

#include "lv2_control_host.hpp"

namespace {

struct Fixture : earshot::fuzz::Lv2ControlHost {
  std::array<float, 32> controls{};
  std::array<float, 64> in{}, left{}, right{};

  Fixture() : Lv2ControlHost(0) {
    controls[7] = 1.0f;
    controls[9] = 2.0f;
    for (std::uint32_t p = 5; p < 22; ++p) desc->connect_port(handle, p, &controls[p]);
    desc->connect_port(handle, 0, in.data());
    desc->connect_port(handle, 1, left.data());
    desc->connect_port(handle, 2, right.data());
    desc->connect_port(handle, 3, control.data());
    desc->connect_port(handle, 4, notify.data());
    desc->activate(handle);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Fixture f;  // one instance: the default set is prepared once
  if (size == 0 || !f.handle) return 0;
  f.control.fill(0);
  const std::uint8_t* rest = data + 1;
  const std::size_t n = std::min<std::size_t>(size - 1, 4000);
  switch (data[0] % 4) {
    case 0: f.raw(rest, size - 1); break;
    case 1: f.message(f.id(LV2_PATCH__Set), "urn:earshot:lv2:panner#sofa", f.id(LV2_ATOM__Path), rest, n); break;
    case 2: f.message(f.id(LV2_PATCH__Set), "urn:earshot:lv2:panner#tracker", f.id(LV2_ATOM__String), rest, n); break;
    default: f.message(f.id(LV2_PATCH__Get), nullptr, 0, rest, 0); break;
  }
  f.run(64);
  return 0;
}
