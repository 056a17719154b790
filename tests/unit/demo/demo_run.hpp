#pragma once
// Helpers of the demo tests: run the earshot binary, read what it wrote.
#include <cstdio>
#include <cstring>
#include <iterator>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace earshot::testing {

struct Run {
  int status = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs a shell command, capturing its output.
inline Run run(const std::string& cmd) {
  Run r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, p)) r.output += buf;
  r.status = pclose(p);
  return r;
}

/// A 32-bit float stereo WAV as written by `earshot demo --capture`: left, right.
inline std::pair<std::vector<float>, std::vector<float>> read_float_wav(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(f)), {});
  std::pair<std::vector<float>, std::vector<float>> lr;
  if (bytes.size() < 44) return lr;
  const std::size_t n = (bytes.size() - 44) / 8;
  lr.first.resize(n), lr.second.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::memcpy(&lr.first[i], bytes.data() + 44 + 8 * i, 4);
    std::memcpy(&lr.second[i], bytes.data() + 48 + 8 * i, 4);
  }
  return lr;
}

}  // namespace earshot::testing
