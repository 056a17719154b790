#include "earshot/errors.hpp"

namespace earshot {

InputError InputError::at(std::string_view origin, long line, std::string_view field,
                          std::string_view message) {
  std::string s(origin);
  if (line > 0) {  // appended piecewise: g++ 12 warns (-Wrestrict, falsely) on ":" + string
    s += ':';
    s += std::to_string(line);
  }
  s += ": ";
  if (!field.empty()) {
    s += "field '";
    s += field;
    s += "': ";
  }
  s += message;
  return InputError(s);
}

}  // namespace earshot
