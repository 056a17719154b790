// A minimal LV2 host for fuzzing a plugin's control port: a URID map, the
// feature array holding it (no worker: a path or spec set by a message is
// only parsed and stored, never opened or started), the control and notify
// buffers, and the two ways a fuzz input becomes a control sequence.
#pragma once

#include <lv2/atom/forge.h>
#include <lv2/core/lv2.h>
#include <lv2/patch/patch.h>
#include <lv2/urid/urid.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

extern "C" const LV2_Descriptor* lv2_descriptor(std::uint32_t index);

namespace earshot::fuzz {

struct Lv2ControlHost {
  std::vector<std::string> uris;
  LV2_URID_Map map{this, [](LV2_URID_Map_Handle h, const char* uri) -> LV2_URID {
                     auto& u = static_cast<Lv2ControlHost*>(h)->uris;
                     for (std::size_t i = 0; i < u.size(); ++i)
                       if (u[i] == uri) return static_cast<LV2_URID>(i + 1);
                     u.emplace_back(uri);
                     return static_cast<LV2_URID>(u.size());
                   }};
  LV2_Feature map_feature{LV2_URID__map, &map};
  std::array<const LV2_Feature*, 2> features{&map_feature, nullptr};
  const LV2_Descriptor* desc;
  LV2_Handle handle = nullptr;
  std::array<std::uint64_t, 1024> control{}, notify{};

  /// Instantiates the bundle's plugin number `index` at 48 kHz.
  explicit Lv2ControlHost(std::uint32_t index) : desc(lv2_descriptor(index)) {
    handle = desc->instantiate(desc, 48000.0, "", features.data());
  }
  Lv2ControlHost(const Lv2ControlHost&) = delete;
  Lv2ControlHost& operator=(const Lv2ControlHost&) = delete;

  LV2_URID id(const char* uri) { return map.map(this, uri); }

  /// A sequence of one object of type `otype`; with `property`, a
  /// patch:property / patch:value pair whose value is `text` typed `type`.
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

  /// A sequence whose body is the fuzz input as it stands.
  void raw(const std::uint8_t* body, std::size_t n) {
    auto* seq = reinterpret_cast<LV2_Atom_Sequence*>(control.data());
    n = std::min(n, sizeof control - sizeof(LV2_Atom));
    seq->atom.type = id(LV2_ATOM__Sequence);
    seq->atom.size = static_cast<std::uint32_t>(n);
    std::memcpy(&seq->body, body, n);
  }

  /// One block of `frames` with the control sequence as it is now.
  void run(std::uint32_t frames) {
    auto* out = reinterpret_cast<LV2_Atom_Sequence*>(notify.data());
    out->atom.size = sizeof notify - sizeof(LV2_Atom);
    desc->run(handle, frames);
  }
};

}  // namespace earshot::fuzz
