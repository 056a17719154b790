#include "earshot/host/world_handle.hpp"

#include <stdexcept>

#include "earshot/errors.hpp"

namespace earshot::host {

void throw_plugin_error(ESenum e, const std::string& message) {
  if (e == ES_INVALID_VALUE || e == ES_HRTF_ERROR) throw InputError(message);
  throw std::runtime_error(message + " (" + esGetErrorString(e) + ")");
}

WorldHandle::WorldHandle(const ESworldparams& p) {
  // esGetErrorMessage(0): why this thread's esCreateWorld failed.
  if (const ESenum e = esCreateWorld(&p, &w_); e != ES_OK) throw_plugin_error(e, esGetErrorMessage(0));
}

WorldHandle::~WorldHandle() { (void)esDestroyWorld(w_); }

void WorldHandle::fail(ESenum e, std::string_view origin, std::string_view field) const {
  throw_plugin_error(e, InputError::at(origin, 0, field, esGetErrorMessage(w_)).what());
}

}  // namespace earshot::host
