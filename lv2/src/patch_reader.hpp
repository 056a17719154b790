// The patch messages in a control port's atom sequence, read without
// trusting the host's bytes: every event, object property and value must lie
// inside the size the sequence states, and reading stops at the first event
// that does not (tests/fuzz/fuzz_lv2_control.cpp, fuzz_lv2_ambi_control.cpp).
// Reads only, allocates nothing: it runs on the audio thread.
#pragma once

#include <lv2/atom/atom.h>
#include <lv2/atom/util.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

namespace earshot::lv2 {

/// Calls on_get() for every patch:Get and on_set(key, value, text) for every
/// patch:Set whose patch:property is a URID and that has a patch:value
/// (`text`: the value's bytes up to its first NUL, for string and path
/// values). `uris` maps the atom and patch URIs (atom_object,
/// atom_resource, atom_urid, patch_get, patch_set, patch_property,
/// patch_value).
template <class Uris, class OnGet, class OnSet>
void read_patch_messages(const LV2_Atom_Sequence* seq, const Uris& uris, OnGet&& on_get, OnSet&& on_set) {
  if (!seq || seq->atom.size < sizeof(LV2_Atom_Sequence_Body)) return;
  const auto* end = reinterpret_cast<const std::uint8_t*>(&seq->body) + seq->atom.size;
  const auto inside = [end](const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    return b <= end && n <= static_cast<std::size_t>(end - b);
  };
  LV2_ATOM_SEQUENCE_FOREACH(seq, ev) {
    if (!inside(ev, sizeof(LV2_Atom_Event)) || !inside(&ev->body, sizeof(LV2_Atom) + ev->body.size)) return;
    if (ev->body.type != uris.atom_object && ev->body.type != uris.atom_resource) continue;
    if (ev->body.size < sizeof(LV2_Atom_Object_Body)) continue;
    const auto* obj = reinterpret_cast<const LV2_Atom_Object*>(&ev->body);
    if (obj->body.otype == uris.patch_get) {
      on_get();
      continue;
    }
    if (obj->body.otype != uris.patch_set) continue;
    const LV2_Atom* property = nullptr;
    const LV2_Atom* value = nullptr;
    LV2_ATOM_OBJECT_FOREACH(obj, prop) {
      if (!inside(prop, sizeof(LV2_Atom_Property_Body)) || !inside(&prop->value, sizeof(LV2_Atom) + prop->value.size))
        break;
      if (prop->key == uris.patch_property) property = &prop->value;
      if (prop->key == uris.patch_value) value = &prop->value;
    }
    if (!property || property->type != uris.atom_urid || property->size < sizeof(LV2_URID) || !value) continue;
    const LV2_URID key = reinterpret_cast<const LV2_Atom_URID*>(property)->body;
    const auto* text = static_cast<const char*>(LV2_ATOM_BODY_CONST(value));
    on_set(key, value, std::string_view(text, strnlen(text, value->size)));
  }
}

}  // namespace earshot::lv2
