// The LV2 Ambisonic decoder's control port (ambi_plugin.cpp, order 1): the
// atom sequence a host hands run(). The first byte picks what the rest is:
// 0 the raw sequence body (events, objects, properties with any sizes), 1 a
// patch:Set of the tracker spec, 2 a patch:Get. No worker is offered, so a
// spec is only parsed and stored, never started.
#include <lv2/atom/forge.h>
#include <lv2/core/lv2.h>
#include <lv2/patch/patch.h>
#include <lv2/urid/urid.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

extern "C" const LV2_Descriptor* lv2_descriptor(std::uint32_t index);

namespace {

constexpr std::uint32_t kInputs = 4;  // order 1

struct Fixture {
  std::vector<std::string> uris;
  LV2_URID_Map map{this, [](LV2_URID_Map_Handle h, const char* uri) -> LV2_URID {
                     auto& u = static_cast<Fixture*>(h)->uris;
                     for (std::size_t i = 0; i < u.size(); ++i)
                       if (u[i] == uri) return static_cast<LV2_URID>(i + 1);
                     u.emplace_back(uri);
                     return static_cast<LV2_URID>(u.size());
                   }};
  LV2_Feature map_feature{LV2_URID__map, &map};
  std::array<const LV2_Feature*, 2> features{&map_feature, nullptr};
  const LV2_Descriptor* desc = lv2_descriptor(1);
  LV2_Handle handle = nullptr;
  std::array<float, 16> controls{};
  std::array<std::array<float, 64>, kInputs> in{};
  std::array<float, 64> left{}, right{};
  std::array<std::uint64_t, 1024> control{}, notify{};

  Fixture() {
    handle = desc->instantiate(desc, 48000.0, "", features.data());
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
  LV2_URID id(const char* uri) { return map.map(this, uri); }

  void message(LV2_URID otype, const char* property, LV2_URID type, const std::uint8_t* text, std::size_t n) {
    LV2_Atom_Forge forge;
    lv2_atom_forge_init(&forge, &map);
    lv2_atom_forge_set_buffer(&forge, reinterpret_cast<std::uint8_t*>(control.data()), sizeof control);
    LV2_Atom_Forge_Frame seq, obj;
    lv2_atom_forge_sequence_head(&forge, &seq, 0);
    lv2_atom_forge_frame_time(&forge, 0);
    lv2_atom_forge_object(&forge, &obj, 0, otype);
    if (property) {
      lv2_atom_forge_key(&forge, id(LV2_PATCH__property));
      lv2_atom_forge_urid(&forge, id(property));
      lv2_atom_forge_key(&forge, id(LV2_PATCH__value));
      lv2_atom_forge_typed_string(&forge, type, reinterpret_cast<const char*>(text), static_cast<std::uint32_t>(n));
    }
    lv2_atom_forge_pop(&forge, &obj);
    lv2_atom_forge_pop(&forge, &seq);
  }

  void raw(const std::uint8_t* body, std::size_t n) {
    auto* seq = reinterpret_cast<LV2_Atom_Sequence*>(control.data());
    n = std::min(n, sizeof control - sizeof(LV2_Atom));
    seq->atom.type = id(LV2_ATOM__Sequence);
    seq->atom.size = static_cast<std::uint32_t>(n);
    std::memcpy(&seq->body, body, n);
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
  auto* notify = reinterpret_cast<LV2_Atom_Sequence*>(f.notify.data());
  notify->atom.size = sizeof f.notify - sizeof(LV2_Atom);
  f.desc->run(f.handle, 64);
  return 0;
}
