#include "earshot/audio/cache_files.hpp"

#include <fcntl.h>
#include <unistd.h>
#define XXH_INLINE_ALL  // header only: no library to link into the plugin
#include <xxhash.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <exception>
#include <system_error>
#include <utility>
#include <vector>

namespace earshot::audio::cache_files {

namespace fs = std::filesystem;

std::array<std::uint8_t, 16> hash128(std::span<const std::uint8_t> bytes) {
  XXH128_canonical_t c;
  XXH128_canonicalFromHash(&c, XXH3_128bits(bytes.data(), bytes.size()));
  std::array<std::uint8_t, 16> out{};
  std::memcpy(out.data(), c.digest, 16);
  return out;
}

std::string hex(std::span<const std::uint8_t> bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string s;
  for (const std::uint8_t x : bytes) s += {kDigits[x >> 4], kDigits[x & 15]};
  return s;
}

bool is_ours(const fs::path& p, std::string_view ext) {
  const std::string name = p.filename().string();
  const std::size_t entry = 32 + ext.size();
  if (name.size() < entry || name.compare(32, ext.size(), ext) != 0) return false;
  if (!std::all_of(name.begin(), name.begin() + 32, [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); }))
    return false;
  return name.size() == entry || (name.size() > entry + 4 && name.compare(name.size() - 4, 4, ".tmp") == 0);
}

std::string errno_text(int e) { return std::error_code(e, std::generic_category()).message(); }

std::string write_whole(const fs::path& file, std::span<const std::span<const std::uint8_t>> pieces) {
  static std::atomic<unsigned> serial{0};
  std::string problem;
  fs::path tmp;
  try {
    std::error_code ec;
    fs::create_directories(file.parent_path(), ec);
    tmp = file;
    // Appended piece by piece: g++ 12 warns of an overlapping copy in the
    // inlined '"." + std::to_string(...)' (GCC bug 105651).
    tmp += ".";
    tmp += std::to_string(::getpid());
    tmp += ".";
    tmp += std::to_string(serial++);
    tmp += ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) return errno_text(errno);
    for (const auto piece : pieces) {
      const std::uint8_t* p = piece.data();
      std::size_t n = piece.size();
      while (n > 0 && problem.empty()) {
        const ssize_t k = ::write(fd, p, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) problem = errno_text(k < 0 ? errno : ENOSPC);
        if (k > 0) p += k, n -= static_cast<std::size_t>(k);
      }
    }
    if (::close(fd) != 0 && problem.empty()) problem = errno_text(errno);
    if (problem.empty() && ::rename(tmp.c_str(), file.c_str()) != 0) problem = errno_text(errno);
  } catch (const std::exception& e) {
    problem = e.what();
  }
  if (!problem.empty() && !tmp.empty()) {
    std::error_code ec;
    fs::remove(tmp, ec);
  }
  return problem;
}

void prune(const fs::path& dir, std::string_view ext, std::size_t keep) {
  std::error_code ec;
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  const auto stale_tmp = fs::file_time_type::clock::now() - std::chrono::hours(1);
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& p = it->path();
    if (!is_ours(p, ext)) continue;
    std::error_code e2;
    const auto t = fs::last_write_time(p, e2);
    if (e2) continue;
    if (p.extension() == ext) files.emplace_back(t, p);
    if (p.extension() == ".tmp" && t < stale_tmp) fs::remove(p, e2);
  }
  if (files.size() <= keep) return;
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = keep; i < files.size(); ++i) fs::remove(files[i].second, ec);
}

}  // namespace earshot::audio::cache_files
