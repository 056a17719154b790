// The host's feature array, read defensively: a plugin must survive what
// real hosts hand it. Debian's lv2file passes an entry whose URI is NULL
// (it crashed the plugin at instantiate, which compared every URI); an entry
// itself may be NULL only as the terminator. Entries without a URI are
// skipped, never dereferenced further; so are those after kMaxFeatures (a
// host whose array is not terminated would otherwise be read forever).
#pragma once

#include <lv2/core/lv2.h>

#include <cstring>

namespace earshot::lv2 {

/// More features than any host passes (jalv passes ~15).
inline constexpr int kMaxFeatures = 256;

/// The data of the feature `uri` in the host's array, or nullptr when the
/// array is NULL or holds no such feature.
inline const void* feature_data(const LV2_Feature* const* features, const char* uri) {
  for (int i = 0; features && i < kMaxFeatures && features[i]; ++i) {
    const char* u = features[i]->URI;
    if (u && std::strcmp(u, uri) == 0) return features[i]->data;
  }
  return nullptr;
}

}  // namespace earshot::lv2
