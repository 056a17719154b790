// lv2_cost: what the LV2 plugin costs per block in lilv's own benchmark
// host (lv2bench, lilv-utils), beside one source through the plugin's C API
// world (the path `earshot render` takes: esRender per block), in the same
// run and at the same block sizes. Prints markdown for docs/BENCHMARKS.md.
//
//   lv2_cost [--seconds 10] [--repeat 5] [--calls 400000]
//
// lv2bench times run() over N frames with its own buffers (silence in, our
// latency FIFO and 128-frame renderer inside); the world renders a callback
// source of noise at 60 degrees with block_size B. Medians of --repeat runs.
// Then the spread of single run() calls of 128 frames (the plugin loaded
// with dlopen, noise in, this thread at SCHED_FIFO when allowed) beside a
// busy loop of similar length timed the same way: the loop's worst cases are
// the machine's own stalls (a VM's vCPU preempted), not the plugin's.
// Timing only: nothing here asserts; its test is a smoke run.
#include <dlfcn.h>
#include <lv2/core/lv2.h>
#include <lv2/urid/urid.h>
#include <pthread.h>
#include <sched.h>
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

double mono_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Spread {
  double median_us, p99_us, p9999_us, max_us;
  int over_budget;  // calls longer than a 128-frame period at 48 kHz
};

Spread spread(std::vector<double> t) {
  int over = 0;
  for (double x : t) over += x > 128.0 / 48000.0 ? 1 : 0;
  std::sort(t.begin(), t.end());
  const auto at = [&](double q) { return t[std::min(t.size() - 1, static_cast<std::size_t>(q * double(t.size())))] * 1e6; };
  return {at(0.5), at(0.99), at(0.9999), t.back() * 1e6, over};
}

/// run(128) times of the plugin binary, `calls` of them.
std::vector<double> run_times(std::size_t calls) {
  std::vector<double> t;
  void* dl = dlopen(EARSHOT_LV2_PATH "/earshot.lv2/earshot.so", RTLD_NOW | RTLD_LOCAL);
  if (!dl) return t;
  const auto fn = reinterpret_cast<LV2_Descriptor_Function>(dlsym(dl, "lv2_descriptor"));
  const LV2_Descriptor* d = fn ? fn(0) : nullptr;
  struct Map {
    std::vector<std::string> uris;
  } names;
  LV2_URID_Map map{&names, [](LV2_URID_Map_Handle h, const char* uri) -> LV2_URID {
                     auto& u = static_cast<Map*>(h)->uris;
                     for (std::size_t i = 0; i < u.size(); ++i)
                       if (u[i] == uri) return static_cast<LV2_URID>(i + 1);
                     u.emplace_back(uri);
                     return static_cast<LV2_URID>(u.size());
                   }};
  LV2_Feature feature{LV2_URID__map, &map};
  const LV2_Feature* features[] = {&feature, nullptr};
  LV2_Handle h = d ? d->instantiate(d, 48000, "", features) : nullptr;
  if (!h) return t;
  std::vector<float> controls(32, 0.0f), in(128), l(128), r(128);
  controls[5] = 60.0f;   // azimuth
  controls[7] = 1.0f;    // distance
  controls[9] = 2.0f;    // inverse clamped
  controls[11] = -12.0f; // reverb send
  for (std::uint32_t p = 5; p < 22; ++p) d->connect_port(h, p, &controls[p]);
  d->connect_port(h, 0, in.data());
  d->connect_port(h, 1, l.data());
  d->connect_port(h, 2, r.data());
  d->activate(h);
  Noise noise;
  t.reserve(calls);
  for (std::size_t i = 0; i < calls; ++i) {
    std::copy_n(noise.samples.begin() + static_cast<std::ptrdiff_t>((i * 128) % (noise.samples.size() - 128)), 128, in.begin());
    const double a = mono_s();
    d->run(h, 128);
    t.push_back(mono_s() - a);
  }
  d->cleanup(h);
  dlclose(dl);
  return t;
}

/// A busy loop of about the same length, timed the same way.
std::vector<double> control_times(std::size_t calls, double typical_s) {
  volatile double sink = 0;
  std::size_t spins = 100;
  for (;;) {  // size the loop to the plugin's median
    const double a = mono_s();
    for (std::size_t k = 0; k < spins; ++k) sink = sink + double(k) * 0.5;
    if (mono_s() - a >= typical_s || spins > 100000000) break;
    spins *= 2;
  }
  std::vector<double> t;
  t.reserve(calls);
  for (std::size_t i = 0; i < calls; ++i) {
    const double a = mono_s();
    for (std::size_t k = 0; k < spins; ++k) sink = sink + double(k) * 0.5;
    t.push_back(mono_s() - a);
  }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"LV2 plugin cost per block (lv2bench) beside the C API world"};
  double seconds = 10;
  int repeat = 5;
  int spread_calls = 400000;
  app.add_option("--seconds", seconds, "Audio per measurement, seconds")->capture_default_str();
  app.add_option("--repeat", repeat, "Runs per figure (median)")->capture_default_str()->check(CLI::Range(1, 100));
  app.add_option("--calls", spread_calls, "run() calls timed one by one, and as many of the control loop")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000000));
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

  // Real-time priority where allowed (root or rtprio), as a host's audio thread.
  sched_param sp{};
  sp.sched_priority = 60;
  const bool fifo = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
  const auto calls = static_cast<std::size_t>(spread_calls);
  const auto plugin = run_times(calls);
  if (plugin.empty()) {
    std::fprintf(stderr, "lv2_cost: cannot load the plugin binary from %s\n", EARSHOT_LV2_PATH);
    return 1;
  }
  const Spread p = spread(plugin);
  const Spread c = spread(control_times(calls, p.median_us * 1e-6));
  std::printf("\n%zu calls%s; budget %.0f us (128 frames at 48 kHz)\n\n", calls, fifo ? " at SCHED_FIFO 60" : "",
              128.0 / 48000.0 * 1e6);
  std::printf("| timed | median us | p99 us | p99.99 us | max us | over budget |\n|---|---:|---:|---:|---:|---:|\n");
  std::printf("| plugin run(128) | %.1f | %.1f | %.1f | %.0f | %d |\n", p.median_us, p.p99_us, p.p9999_us, p.max_us,
              p.over_budget);
  std::printf("| busy loop about as long (control) | %.1f | %.1f | %.1f | %.0f | %d |\n", c.median_us, c.p99_us,
              c.p9999_us, c.max_us, c.over_budget);
  return 0;
}
