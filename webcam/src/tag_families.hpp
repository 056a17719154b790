// libapriltag's tag families by name (create and destroy functions).
#pragma once

#include <apriltag/apriltag.h>

#include <memory>
#include <string>
#include <string_view>

namespace earshot::webcam::detail {

struct FamilyDeleter {
  void (*destroy)(apriltag_family_t*) = nullptr;
  void operator()(apriltag_family_t* f) const {
    if (f && destroy) destroy(f);
  }
};
using FamilyPtr = std::unique_ptr<apriltag_family_t, FamilyDeleter>;

/// The family, or throws std::invalid_argument naming it and the known ones.
FamilyPtr create_family(std::string_view name);

/// "tag36h11, tag25h9, ..."
std::string family_names();

}  // namespace earshot::webcam::detail
