// Errors about outside input: they name where the problem is (file, line, field).
#pragma once

#include <stdexcept>
#include <string>

namespace earshot {

/// Bad input from a file, a packet or a user. what() reads e.g.
///   "dots.csv:12: field 'x3': not a number: 'abc'"
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;

  /// "origin:line: field 'field': message" (line <= 0 or empty field are left out).
  static InputError at(std::string_view origin, long line, std::string_view field,
                       std::string_view message);
};

}  // namespace earshot
