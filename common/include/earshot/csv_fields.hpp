// Splitting and number parsing for the project's CSV files (Dots, Poses, Pose track).
#pragma once

#include <array>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "earshot/errors.hpp"

namespace earshot::csv {

/// Splits a line at commas (no quoting: these files hold numbers and words).
inline std::vector<std::string_view> split(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::vector<std::string_view> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      out.push_back(line.substr(start));
      return out;
    }
    out.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

/// Splits a line at commas into `out` without allocating: returns the number
/// of fields in the line, which may exceed out.size() (the rest are not kept).
template <size_t N>
size_t split_into(std::string_view line, std::array<std::string_view, N>& out) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  size_t n = 0, start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    const std::string_view field = line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    if (n < N) out[n] = field;
    ++n;
    if (comma == std::string_view::npos) return n;
    start = comma + 1;
  }
}

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

/// A finite number, or nullopt for an empty field; throws for anything else.
inline std::optional<double> optional_number(std::string_view field, std::string_view origin,
                                             long line, std::string_view name) {
  field = trim(field);
  if (field.empty()) return std::nullopt;
  double v = 0.0;
  const char* first = field.data();
  if (*first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, field.data() + field.size(), v);
  if (ec != std::errc() || ptr != field.data() + field.size())
    throw InputError::at(origin, line, name, "not a number: '" + std::string(field) + "'");
  if (!std::isfinite(v))
    throw InputError::at(origin, line, name, "not a finite number: '" + std::string(field) + "'");
  return v;
}

inline double number(std::string_view field, std::string_view origin, long line,
                     std::string_view name) {
  auto v = optional_number(field, origin, line, name);
  if (!v) throw InputError::at(origin, line, name, "missing value");
  return *v;
}

}  // namespace earshot::csv
