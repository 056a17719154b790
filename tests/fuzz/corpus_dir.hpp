// Where a fuzz target may write its seed inputs: binary seeds are made at
// start-up (LLVMFuzzerInitialize) instead of being committed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string_view>
#include <system_error>

namespace earshot::fuzz {

/// The corpus directory libFuzzer was given: the last argument that is not
/// a flag, if it is a directory.
inline std::optional<std::filesystem::path> corpus_dir(int argc, char** argv) {
  for (int i = argc - 1; i > 0; --i) {
    const std::filesystem::path p = argv[i];
    if (std::string_view(argv[i]).starts_with("-")) continue;
    std::error_code ec;
    if (std::filesystem::is_directory(p, ec)) return p;
    return std::nullopt;
  }
  return std::nullopt;
}

/// Writes `bytes` as the seed `name` in `dir`.
inline void write_seed(const std::filesystem::path& dir, std::string_view name, std::span<const std::uint8_t> bytes) {
  std::ofstream(dir / name, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace earshot::fuzz
