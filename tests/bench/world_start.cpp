// world_start: what a world costs before its first block, and what many
// worlds rendering at once cost, through the plugin's C API (as a game or a
// plugin host pays it), beside OpenAL Soft's context creation with HRTF on
// its loopback device in the same run. Prints markdown for docs/BENCHMARKS.md.
//
//   world_start [--later N] [--worlds 8] [--blocks 2000] [--sources 16] [--first-runs 5]
//
// Rows:
//  - the first world of a process (the default SOFA set), each the median
//    of R fresh processes (this program run again with --first-world): with
//    the disk cache off, empty (prepares the set and writes the file) and
//    filled (reads the file); then the median of N later worlds in this
//    process (each destroyed before the next), wall and CPU milliseconds;
//    the cache file's size and what hashing the SOFA file costs;
//  - OpenAL Soft: the first and later contexts with HRTF (48 kHz loopback);
//  - W worlds rendering S moving sources each on W threads at once against
//    one world rendering alone: CPU per block per world.
// Timing only: nothing here asserts, the test registered for it is a smoke run.
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#include <AL/al.h>
#include <AL/alc.h>
#include <AL/alext.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <filesystem>
#include <fstream>

#include "earshot/earshot.h"

namespace {

double now_s(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Cost {
  double wall_ms = 0.0, cpu_ms = 0.0;
};

template <class F>
Cost measure(F&& f) {
  const double w0 = now_s(CLOCK_MONOTONIC), c0 = now_s(CLOCK_PROCESS_CPUTIME_ID);
  f();
  return {1e3 * (now_s(CLOCK_MONOTONIC) - w0), 1e3 * (now_s(CLOCK_PROCESS_CPUTIME_ID) - c0)};
}

Cost median(std::vector<Cost> v) {
  std::sort(v.begin(), v.end(), [](const Cost& a, const Cost& b) { return a.wall_ms < b.wall_ms; });
  return v[v.size() / 2];
}

void check(ESenum e, const char* what) {
  if (e != ES_OK) throw std::runtime_error(std::string(what) + ": " + esGetErrorString(e));
}

ESworld create_world() {
  ESworldparams p;
  esWorldParamsDefault(&p);
  ESworld w = 0;
  check(esCreateWorld(&p, &w), "esCreateWorld");
  return w;
}

// ---- OpenAL Soft, the reference ----

struct AlLoopback {
  LPALCLOOPBACKOPENDEVICESOFT open = nullptr;
  LPALCISRENDERFORMATSUPPORTEDSOFT supported = nullptr;
  AlLoopback() {
    open = reinterpret_cast<LPALCLOOPBACKOPENDEVICESOFT>(alcGetProcAddress(nullptr, "alcLoopbackOpenDeviceSOFT"));
    if (!open) throw std::runtime_error("OpenAL Soft: no loopback device extension");
  }
};

/// One context with HRTF at 48 kHz stereo float, created and destroyed.
Cost openal_context(const AlLoopback& al) {
  ALCdevice* dev = al.open(nullptr);
  if (!dev) throw std::runtime_error("OpenAL Soft: cannot open a loopback device");
  const ALCint attrs[] = {ALC_FORMAT_CHANNELS_SOFT, ALC_STEREO_SOFT, ALC_FORMAT_TYPE_SOFT, ALC_FLOAT_SOFT,
                          ALC_FREQUENCY, 48000, ALC_HRTF_SOFT, ALC_TRUE, 0};
  ALCcontext* ctx = nullptr;
  const Cost c = measure([&] { ctx = alcCreateContext(dev, attrs); });
  if (!ctx) throw std::runtime_error("OpenAL Soft: cannot create a context");
  alcDestroyContext(ctx);
  alcCloseDevice(dev);
  return c;
}

// ---- many worlds ----

/// A world with `sources` looping noise sources circling the head.
struct BusyWorld {
  ESworld w = 0;
  std::vector<ESsource> sources;
  std::vector<float> left, right;
  std::uint64_t block = 0;

  BusyWorld(int n_sources, unsigned seed) : w(create_world()), left(128), right(128) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.1f, 0.1f);
    std::vector<float> noise(48000);
    for (float& x : noise) x = u(rng);
    ESbuffer buf = 0;
    check(esCreateBuffer(w, noise.data(), static_cast<ESuint>(noise.size()), 48000, &buf), "esCreateBuffer");
    for (int i = 0; i < n_sources; ++i) {
      ESsource s = 0;
      check(esCreateSource(w, &s), "esCreateSource");
      check(esSourcei(w, s, ES_BUFFER, static_cast<ESint>(buf)), "ES_BUFFER");
      check(esSourcei(w, s, ES_LOOPING, ES_TRUE), "ES_LOOPING");
      check(esSourcePlay(w, s), "esSourcePlay");
      sources.push_back(s);
    }
  }
  ~BusyWorld() {
    esSetControlThread(w);  // back from the thread that rendered it
    esDestroyWorld(w);
  }
  BusyWorld(const BusyWorld&) = delete;
  BusyWorld& operator=(const BusyWorld&) = delete;

  void render_block() {
    const double t = static_cast<double>(block++) * 128.0 / 48000.0;
    for (std::size_t i = 0; i < sources.size(); ++i) {
      const double a = 0.5 * t + 6.283 * static_cast<double>(i) / static_cast<double>(sources.size());
      esSource3f(w, sources[i], ES_POSITION, static_cast<float>(2.0 * std::sin(a)), 0.0f,
                 static_cast<float>(-2.0 * std::cos(a)));
    }
    esRender(w, left.data(), right.data(), 128);
  }
};

/// CPU microseconds per block per world, `worlds` rendering at once.
double per_block_us(int worlds, int sources, int blocks) {
  std::vector<std::unique_ptr<BusyWorld>> ws;
  for (int i = 0; i < worlds; ++i) ws.push_back(std::make_unique<BusyWorld>(sources, static_cast<unsigned>(i + 1)));
  for (auto& w : ws) w->render_block();  // warm
  const double c0 = now_s(CLOCK_PROCESS_CPUTIME_ID);
  std::vector<std::thread> threads;
  for (auto& w : ws)
    threads.emplace_back([&w, blocks] {
      // Each world's control and audio calls come from this one thread.
      esSetControlThread(w->w);
      for (int b = 0; b < blocks; ++b) w->render_block();
    });
  for (auto& t : threads) t.join();
  return 1e6 * (now_s(CLOCK_PROCESS_CPUTIME_ID) - c0) / (static_cast<double>(blocks) * worlds);
}

int arg_int(int argc, char** argv, const char* name, int fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], name) == 0) return std::atoi(argv[i + 1]);
  return fallback;
}

// ---- the first world of a process, by disk cache ----

/// Runs this program again with --first-world and EARSHOT_CACHE_DIR=`cache`:
/// the cost of that process's first world.
Cost first_world_in_new_process(const std::string& cache) {
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const std::string cmd = "EARSHOT_CACHE_DIR='" + cache + "' '" + self + "' --first-world";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) throw std::runtime_error("cannot run " + cmd);
  Cost c;
  const int got = std::fscanf(p, "%lf %lf", &c.wall_ms, &c.cpu_ms);
  if (pclose(p) != 0 || got != 2) throw std::runtime_error("the child process failed: " + cmd);
  return c;
}

std::uintmax_t cache_bytes(const std::filesystem::path& dir) {
  std::uintmax_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".hrtf") n += e.file_size();
  return n;
}

/// Reading and hashing the default SOFA file as the disk cache's key does
/// (XXH3-128), median of 20, milliseconds.
double hash_ms() {
  std::vector<double> ms;
  volatile std::uint64_t sink = 0;
  for (int i = 0; i < 20; ++i) {
    const double t0 = now_s(CLOCK_MONOTONIC);
    std::ifstream in("/usr/share/libmysofa/MIT_KEMAR_normal_pinna.sofa", std::ios::binary | std::ios::ate);
    std::vector<char> bytes(static_cast<std::size_t>(in.tellg()));
    in.seekg(0);
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    sink = sink + XXH3_128bits(bytes.data(), bytes.size()).low64;
    ms.push_back(1e3 * (now_s(CLOCK_MONOTONIC) - t0));
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc == 2 && std::strcmp(argv[1], "--first-world") == 0) {
    ESworld w = 0;
    const Cost c = measure([&] { w = create_world(); });
    esDestroyWorld(w);
    std::printf("%.3f %.3f\n", c.wall_ms, c.cpu_ms);
    return 0;
  }
  const int later = std::max(1, arg_int(argc, argv, "--later", 20));
  const int worlds = std::max(1, arg_int(argc, argv, "--worlds", 8));
  const int blocks = std::max(1, arg_int(argc, argv, "--blocks", 2000));
  const int sources = std::max(1, arg_int(argc, argv, "--sources", 16));
  const int first_runs = std::max(1, arg_int(argc, argv, "--first-runs", 5));

  // The disk cache lives in a fresh temporary directory (never the user's):
  // emptied before each "empty" run, left filled for the "filled" ones.
  // Named by this process's id; create_directory fails rather than reuse one.
  const std::filesystem::path cache_dir =
      std::filesystem::temp_directory_path() / ("earshot_world_start_" + std::to_string(getpid()));
  if (!std::filesystem::create_directory(cache_dir))
    throw std::runtime_error("cannot make the temporary directory " + cache_dir.string());
  std::vector<Cost> off, empty, filled;
  for (int i = 0; i < first_runs; ++i) {
    off.push_back(first_world_in_new_process("off"));
    std::filesystem::remove_all(cache_dir);
    std::filesystem::create_directories(cache_dir);
    empty.push_back(first_world_in_new_process(cache_dir.string()));
    filled.push_back(first_world_in_new_process(cache_dir.string()));
  }
  const std::uintmax_t file_bytes = cache_bytes(cache_dir);
  std::filesystem::remove_all(cache_dir);
  // This process's own worlds: no disk cache (the later ones share memory).
  setenv("EARSHOT_CACHE_DIR", "off", 1);

  std::printf("| | wall ms | CPU ms |\n|---|---:|---:|\n");
  const auto row = [&](const char* what, const std::vector<Cost>& cs) {
    const Cost m = median(cs);
    std::printf("| Earshot: first world, %s (median of %d processes) | %.1f | %.1f |\n", what, first_runs, m.wall_ms,
                m.cpu_ms);
  };
  row("disk cache off", off);
  row("disk cache empty (prepares, writes the file)", empty);
  row("disk cache filled (reads the file)", filled);
  ESworld first = 0;
  const Cost c_first = measure([&] { first = create_world(); });
  esDestroyWorld(first);
  std::printf("| Earshot: first world of this process, cache off | %.1f | %.1f |\n", c_first.wall_ms, c_first.cpu_ms);
  std::vector<Cost> cs;
  for (int i = 0; i < later; ++i) {
    ESworld w = 0;
    cs.push_back(measure([&] { w = create_world(); }));
    esDestroyWorld(w);
  }
  const Cost c_later = median(cs);
  std::printf("| Earshot: later world (median of %d) | %.2f | %.2f |\n", later, c_later.wall_ms, c_later.cpu_ms);

  const AlLoopback al;
  const Cost a_first = openal_context(al);
  std::vector<Cost> as;
  for (int i = 0; i < later; ++i) as.push_back(openal_context(al));
  const Cost a_later = median(as);
  std::printf("| OpenAL Soft: first context with HRTF | %.1f | %.1f |\n", a_first.wall_ms, a_first.cpu_ms);
  std::printf("| OpenAL Soft: later context (median of %d) | %.2f | %.2f |\n", later, a_later.wall_ms, a_later.cpu_ms);

  std::printf("\nDisk cache file of the default set (48 kHz, 128-frame blocks): %.2f MB; reading and hashing the "
              "SOFA file for its key (XXH3-128): %.2f ms (median of 20).\n",
              static_cast<double>(file_bytes) / 1e6, hash_ms());

  const double one = per_block_us(1, sources, blocks);
  const double many = per_block_us(worlds, sources, blocks);
  std::printf("\n| worlds at once (%d moving sources each, 128-frame blocks) | CPU us per block per world |\n"
              "|---|---:|\n| 1 | %.1f |\n| %d (one thread each) | %.1f (%.2fx) |\n",
              sources, one, worlds, many, many / one);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "world_start: %s\n", e.what());
  return 1;
}
