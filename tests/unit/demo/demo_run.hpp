#pragma once
// Helpers of the demo tests: run the earshot binary, read what it wrote.
#include <sndfile.h>

#include <cstdio>
#include <filesystem>
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

/// A stereo WAV as written by `earshot demo --capture` (libsndfile): left, right.
inline std::pair<std::vector<float>, std::vector<float>> read_float_wav(const std::filesystem::path& path) {
  std::pair<std::vector<float>, std::vector<float>> lr;
  SF_INFO info{};
  SNDFILE* f = sf_open(path.c_str(), SFM_READ, &info);
  if (!f) return lr;
  if (info.channels == 2) {
    std::vector<float> inter(static_cast<std::size_t>(info.frames) * 2);
    const auto n = static_cast<std::size_t>(sf_readf_float(f, inter.data(), info.frames));
    lr.first.resize(n), lr.second.resize(n);
    for (std::size_t i = 0; i < n; ++i) lr.first[i] = inter[2 * i], lr.second[i] = inter[2 * i + 1];
  }
  sf_close(f);
  return lr;
}

}  // namespace earshot::testing
