// An owned plugin world (earshot.h's esCreateWorld / esDestroyWorld) whose
// failing calls become exceptions that say where the bad value came from.
#pragma once

#include <string>
#include <string_view>

#include "earshot/earshot.h"

namespace earshot::host {

/// Throws for a plugin error code: bad input (ES_INVALID_VALUE,
/// ES_HRTF_ERROR) as earshot::InputError(message), anything else -- a bug in
/// the host -- as std::runtime_error "message (<error string>)".
[[noreturn]] void throw_plugin_error(ESenum e, const std::string& message);

/// One plugin world, destroyed on every way out. Its calls must come from
/// the thread that made it (the control thread), except esRender.
class WorldHandle {
 public:
  /// Throws (throw_plugin_error) with the plugin's reason, e.g. "x.sofa: not a SOFA file".
  explicit WorldHandle(const ESworldparams& p);
  ~WorldHandle();
  WorldHandle(const WorldHandle&) = delete;
  WorldHandle& operator=(const WorldHandle&) = delete;

  [[nodiscard]] ESworld id() const { return w_; }

  /// Throws when `e` is not ES_OK: "origin: field 'field': <the plugin's message>".
  void check(ESenum e, std::string_view origin, std::string_view field) const {
    if (e != ES_OK) fail(e, origin, field);
  }
  [[noreturn]] void fail(ESenum e, std::string_view origin, std::string_view field) const;

 private:
  ESworld w_ = 0;
};

}  // namespace earshot::host
