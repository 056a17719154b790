// The files of Earshot's disk caches (prepared HRTF sets, Ambisonic
// decoders): one directory, each entry `<32 hex digits><ext>` named by a
// 128-bit hash of everything it was made from, written whole under a
// temporary name `<entry>.<pid>.<n>.tmp` and renamed into place (a reader
// sees the old file or the new one, never half of one), the least recently
// used beyond a count removed. Nothing else in the directory is touched: it
// may be shared with other programs.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace earshot::audio::cache_files {

/// XXH3's 128-bit hash of `bytes`, in its canonical (big-endian) byte order.
[[nodiscard]] std::array<std::uint8_t, 16> hash128(std::span<const std::uint8_t> bytes);

/// `bytes` as lowercase hex digits.
[[nodiscard]] std::string hex(std::span<const std::uint8_t> bytes);

/// An entry of this cache (`<32 hex digits><ext>`) or its temporary.
[[nodiscard]] bool is_ours(const std::filesystem::path& p, std::string_view ext);

/// What errno `e` means, for a message.
[[nodiscard]] std::string errno_text(int e);

/// Writes `pieces` one after the other to `file` (the directory made if
/// need be) through a temporary and a rename. Returns what went wrong, or
/// an empty string; on failure the temporary is removed.
[[nodiscard]] std::string write_whole(const std::filesystem::path& file, std::span<const std::span<const std::uint8_t>> pieces);

/// Removes the entries with `ext` in `dir` beyond the `keep` most recently
/// used (modified: a read touches its file), and temporaries older than an
/// hour (left by a process that died while writing).
void prune(const std::filesystem::path& dir, std::string_view ext, std::size_t keep);

}  // namespace earshot::audio::cache_files
