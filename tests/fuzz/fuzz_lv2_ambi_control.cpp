// The LV2 Ambisonic decoder's control port (ambi_plugin.cpp, order 1): the
// atom sequence a host hands run(). The first byte picks what the rest is:
// 0 the raw sequence body (events, objects, properties with any sizes), 1 a
// patch:Set of the tracker spec, 2 a patch:Get. No worker is offered, so a
// spec is only parsed and stored, never started.
#include <algorithm>
#include <array>
#include <cstdint>

#include "lv2_control_host.hpp"

namespace {

constexpr std::uint32_t kInputs = 4;  // order 1

struct Fixture : earshot::fuzz::Lv2ControlHost {
  std::array<float, 16> controls{};
  std::array<std::array<float, 64>, kInputs> in{};
  std::array<float, 64> left{}, right{};

  Fixture() : Lv2ControlHost(1) {
    if (!handle) return;
    for (std::uint32_t c = 0; c < kInputs; ++c) desc->connect_port(handle, c, in[c].data());
    desc->connect_port(handle, kInputs, left.data());
    desc->connect_port(handle, kInputs + 1, right.data());
    desc->connect_port(handle, kInputs + 2, control.data());
    desc->connect_port(handle, kInputs + 3, notify.data());
    controls[0] = 1.0f;  // tracking on (no worker: the spec is stored, never started)
    for (std::uint32_t p = 0; p < 10; ++p) desc->connect_port(handle, kInputs + 4 + p, &controls[p]);
    desc->activate(handle);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Fixture f;  // one instance: the decoder is designed once
  if (size == 0 || !f.handle) return 0;
  f.control.fill(0);
  const std::uint8_t* rest = data + 1;
  const std::size_t n = std::min<std::size_t>(size - 1, 4000);
  switch (data[0] % 3) {
    case 0: f.raw(rest, size - 1); break;
    case 1:
      f.message(f.id(LV2_PATCH__Set), "urn:earshot:lv2:ambi-binaural#tracker", f.id(LV2_ATOM__String), rest, n);
      break;
    default: f.message(f.id(LV2_PATCH__Get), nullptr, 0, rest, 0); break;
  }
  f.run(64);
  return 0;
}
