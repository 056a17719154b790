#pragma once
// The demo's keys, in one place: `earshot demo --help`, the terminal's
// "Keys:" line and the window all print this list, so they cannot disagree.
#include <array>
#include <string>

namespace earshot::demo {

struct Key {
  const char* keys;  ///< as typed (lower case; the window takes either case)
  const char* does;
};

inline constexpr std::array<Key, 5> kKeys{{
    {"r", "recenter the head"},
    {"n", "next scene preset"},
    {"m", "next room preset"},
    {"h", "next HRTF set (--hrtf)"},
    {"q or Esc", "quit"},
}};

/// "r recenter the head, n next scene preset, ..."
inline std::string keys_line() {
  std::string s;
  for (const auto& k : kKeys) s += std::string(s.empty() ? "" : ", ") + k.keys + " " + k.does;
  return s;
}

}  // namespace earshot::demo
