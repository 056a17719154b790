// A path under the system's temporary directory that belongs to this test
// process alone. ctest runs every gtest case as its own process, several at a
// time, and CI may run two builds' suites on one machine: a fixed name such as
// /tmp/earshot_x/set.sofa is then written by one process while another reads
// it (a "truncated HDF5" failure seen under ASan). The process id in the name
// keeps them apart; whatever was made under such names is removed when the
// process exits normally.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace earshot::test {

namespace scratch_detail {

inline std::string prefix() { return "earshot_" + std::to_string(::getpid()) + "_"; }

/// Removes this process's scratch files and folders when destroyed (at exit).
struct Cleanup {
  ~Cleanup() {
    std::error_code ec;
    const auto tmp = std::filesystem::temp_directory_path(ec);
    if (ec) return;
    const std::string mine = prefix();
    for (const auto& e : std::filesystem::directory_iterator(tmp, ec))
      if (e.path().filename().string().rfind(mine, 0) == 0) std::filesystem::remove_all(e.path(), ec);
  }
};

}  // namespace scratch_detail

/// temp/earshot_<pid>_<name>; `name` may end in an extension.
inline std::filesystem::path scratch_path(const std::string& name) {
  static const scratch_detail::Cleanup cleanup;
  return std::filesystem::temp_directory_path() / (scratch_detail::prefix() + name);
}

}  // namespace earshot::test
