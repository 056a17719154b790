// The URIs of the Earshot LV2 plugin (the turtle in lv2/ttl/ says the same)
// and the URIDs the plugin maps once at instantiation.
#pragma once

#include <lv2/atom/atom.h>
#include <lv2/patch/patch.h>
#include <lv2/urid/urid.h>

namespace earshot::lv2 {

#define EARSHOT_LV2_URI "urn:earshot:lv2:panner"
#define EARSHOT_LV2_SOFA EARSHOT_LV2_URI "#sofa"        /* atom:Path: the HRTF set */
#define EARSHOT_LV2_TRACKER EARSHOT_LV2_URI "#tracker"  /* atom:String: a full tracker spec */
#define EARSHOT_LV2_PROJECT "urn:earshot:lv2:project"  /* the bundle's doap:Project */
#define EARSHOT_LV2_SEND EARSHOT_LV2_URI "#send"        /* atom:String: where the tracker sends its poses */

struct Uris {
  LV2_URID atom_path = 0, atom_string = 0, atom_urid = 0, atom_resource = 0, atom_object = 0, atom_sequence = 0;
  LV2_URID patch_set = 0, patch_get = 0, patch_property = 0, patch_value = 0;
  LV2_URID sofa = 0, tracker = 0, send = 0;

  explicit Uris(const LV2_URID_Map* m) {
    if (!m) return;
    auto map = [m](const char* uri) { return m->map(m->handle, uri); };
    atom_path = map(LV2_ATOM__Path);
    atom_string = map(LV2_ATOM__String);
    atom_urid = map(LV2_ATOM__URID);
    atom_resource = map(LV2_ATOM__Resource);
    atom_object = map(LV2_ATOM__Object);
    atom_sequence = map(LV2_ATOM__Sequence);
    patch_set = map(LV2_PATCH__Set);
    patch_get = map(LV2_PATCH__Get);
    patch_property = map(LV2_PATCH__property);
    patch_value = map(LV2_PATCH__value);
    sofa = map(EARSHOT_LV2_SOFA);
    tracker = map(EARSHOT_LV2_TRACKER);
    send = map(EARSHOT_LV2_SEND);
  }
};

}  // namespace earshot::lv2
