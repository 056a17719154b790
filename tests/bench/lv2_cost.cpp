// lv2_cost: what the LV2 plugin costs per block in lilv's own benchmark
// host (lv2bench, lilv-utils), beside one source through the plugin's C API
// world (the path `earshot render` takes: esRender per block), in the same
// run and at the same block sizes. Prints markdown for docs/BENCHMARKS.md.
//
//   lv2_cost [--seconds 10] [--repeat 5]
//
// lv2bench times run() over N frames with its own buffers (silence in, our
// latency FIFO and 128-frame renderer inside); the world renders a callback
// source of noise at 60 degrees with block_size B. Medians of --repeat runs.
// Timing only: nothing here asserts; its test is a smoke run.
#include <time.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "earshot/earshot.h"

namespace {

double cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// lv2bench's seconds for `frames` frames in blocks of `block`, or -1.
double lv2bench_s(unsigned block, unsigned frames) {
  const std::string cmd = "LV2_PATH='" EARSHOT_LV2_PATH "' lv2bench -b " + std::to_string(block) + " -n " +
                          std::to_string(frames) + " urn:earshot:lv2:panner 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return -1;
  char line[512];
  double seconds = -1;
  while (std::fgets(line, sizeof line, p))
    if (std::string(line).find("urn:earshot:lv2:panner") != std::string::npos) seconds = std::atof(line);
  pclose(p);
  return seconds;
}

/// Precomputed noise, copied out per block: the source costs a memcpy, as
/// lv2bench's input buffer costs nothing.
struct Noise {
  std::vector<float> samples;
  std::size_t at = 0;
  Noise() : samples(1u << 16) {
    std::mt19937 rng{1};
    std::normal_distribution<float> d{0.0f, 0.1f};
    for (auto& x : samples) x = d(rng);
  }
};

/// CPU seconds of `frames` frames through a C API world with one noise source.
double world_s(unsigned block, unsigned frames) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  p.block_size = block;
  ESworld w = 0;
  if (esCreateWorld(&p, &w) != ES_OK) return -1;
  ESsource s = 0;
  esCreateSource(w, &s);
  Noise noise;
  esSourceCallback(
      w, s,
      [](void* user, float* out, ESuint n) {
        auto* nz = static_cast<Noise*>(user);
        if (nz->at + n > nz->samples.size()) nz->at = 0;
        std::copy_n(nz->samples.begin() + static_cast<std::ptrdiff_t>(nz->at), n, out);
        nz->at += n;
      },
      &noise);
  esSource3f(w, s, ES_POSITION, -0.866f, 0.0f, -0.5f);
  esSourcePlay(w, s);
  std::vector<float> l(block), r(block);
  for (int i = 0; i < 8; ++i) esRender(w, l.data(), r.data(), block);  // warm
  const double t0 = cpu_s();
  for (unsigned done = 0; done < frames; done += block) esRender(w, l.data(), r.data(), block);
  const double t = cpu_s() - t0;
  esDestroyWorld(w);
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"LV2 plugin cost per block (lv2bench) beside the C API world"};
  double seconds = 10;
  int repeat = 5;
  app.add_option("--seconds", seconds, "Audio per measurement, seconds")->capture_default_str();
  app.add_option("--repeat", repeat, "Runs per figure (median)")->capture_default_str()->check(CLI::Range(1, 100));
  CLI11_PARSE(app, argc, argv);
  const auto frames = static_cast<unsigned>(seconds * 48000);

  std::printf("| block | lv2bench us/block | C API world us/block | lv2bench / world | lv2bench real-time load |\n");
  std::printf("|---:|---:|---:|---:|---:|\n");
  for (unsigned block : {32u, 64u, 128u, 256u, 512u, 1024u}) {
    std::vector<double> lv, wd;
    for (int i = 0; i < repeat; ++i) {
      lv.push_back(lv2bench_s(block, frames));
      wd.push_back(world_s(block, frames));
    }
    const double blocks = double(frames) / block;
    const double a = median(lv), b = median(wd);
    if (a < 0 || b < 0) {
      std::fprintf(stderr, "lv2_cost: lv2bench or the world failed at block %u (lilv-utils installed?)\n", block);
      return 1;
    }
    std::printf("| %u | %.1f | %.1f | %.2f | %.2f %% |\n", block, a / blocks * 1e6, b / blocks * 1e6, a / b,
                100.0 * a / seconds);
  }
  return 0;
}
