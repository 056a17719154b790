// The message parse_source_spec throws for a spec, for the spec tests.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "earshot/errors.hpp"
#include "earshot/tracker/live/source_spec.hpp"

namespace earshot::tracker::spec_tests {

/// The error parse_source_spec gives `spec` (adds a test failure if it parses).
inline std::string error_of(std::string_view spec, std::string_view field = "--source") {
  try {
    (void)parse_source_spec(spec, field);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "'" << spec << "' parsed";
  return {};
}

}  // namespace earshot::tracker::spec_tests
