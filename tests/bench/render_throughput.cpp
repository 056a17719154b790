// render_throughput: realtime factor (seconds of audio per second of CPU) of
// N moving HRTF sources, Earshot's Renderer against OpenAL Soft in the same
// run: 48 kHz, 128-frame blocks, one thread, full-length default HRIRs
// (MIT KEMAR for Earshot, OpenAL Soft's default-48000 for OpenAL). Each
// source plays its own noise on its own circular path around a still
// listener; positions (and, for OpenAL, velocities, so it applies Doppler
// as Earshot's propagation delay does) are set every block. Prints markdown
// for docs/BENCHMARKS.md.
//
//   render_throughput [--sources 1,8,32,64,128,256] [--max-sources N]
//                     [--seconds 2] [--min-cpu 1] [--repeat 3] [--still]
//                     [--stop-below 0.2] [--only earshot|openal] [--csv FILE]
//                     [--hrtf FILE.sofa] [--no-near-field]
//                     [--blend floored|plain|nearest]
//                     [--quality direct,ambisonic:3]
//
// Each (renderer, N) renders at least --seconds of audio and --min-cpu
// seconds of CPU, --repeat times; the best repeat is kept (least disturbed
// by other load on the machine). --still keeps every source at its start
// (positions still set every block): the cost without filter updates.
// --no-near-field turns Earshot's near field off (the paths pass within the
// default set's 1.4 m shell, where it runs): what it costs. --plain-blend
// blends each direction's filters with the plain barycentric weights (no
// blend floor, hrtf_set.hpp): what the floor saves. The last column is the
// convolutions (measured direction x ear) Earshot ran per source and block.
// --stop-below: a renderer is not run at larger N once its RTF fell below.
// --quality: the renderer tiers to run beside OpenAL Soft, interleaved in
// one run: `direct` (the default) and `ambisonic:N` (every source encoded
// into an order-N bus decoded once per block: audio/renderer.hpp with an
// ambisonics::AmbisonicBus; its decoder designed once before timing). With
// more than the direct tier the table has a column per tier and each tier's
// CPU against OpenAL Soft's.
#include <time.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "earshot/audio/ambisonics/ambisonic_bus.hpp"
#include "earshot/audio/ambisonics/binaural_decoder_design.hpp"
#include "earshot/audio/renderer.hpp"
#include "openal_reference.hpp"

namespace {

constexpr int kRate = 48000;
constexpr std::size_t kBlock = 128;
constexpr std::size_t kLoops = 16;  // distinct noise signals, shared round-robin

using Vec3 = std::array<double, 3>;

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);  // all threads: OpenAL may use helpers
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

/// One second of white noise per loop, each different.
std::vector<std::vector<float>> noise_loops() {
  std::vector<std::vector<float>> loops(kLoops, std::vector<float>(kRate));
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (auto& l : loops)
    for (float& x : l) x = u(rng);
  return loops;
}

/// Source i's circular path around the listener (radius 1-2.75 m, its own
/// speed and direction, bobbing up and down), and the path's velocity.
struct Path {
  double radius, speed, phase, bob_phase;
  [[nodiscard]] Vec3 position(double t) const {
    const double a = phase + speed * t;
    return {radius * std::sin(a), 0.5 * std::sin(0.7 * t + bob_phase), -radius * std::cos(a)};
  }
  [[nodiscard]] Vec3 velocity(double t) const {
    const double a = phase + speed * t;
    return {radius * speed * std::cos(a), 0.35 * std::cos(0.7 * t + bob_phase), radius * speed * std::sin(a)};
  }
};

std::vector<Path> paths(int n) {
  std::vector<Path> p;
  for (int i = 0; i < n; ++i) {
    const double dir = (i % 2) ? -1.0 : 1.0;
    p.push_back({1.0 + 0.25 * (i % 8), dir * (0.3 + 0.05 * (i % 13)), 2 * std::numbers::pi * i / n, 0.37 * i});
  }
  return p;
}

double source_gain(int n) { return 0.5 / std::sqrt(double(n)); }  // keeps the mix off the limiter

struct Budget {
  double seconds, min_cpu;
  bool still;  // sources stay at their t = 0 positions
  bool near_field = true;  // Earshot's near field (sources nearer than the set's shell)
};

/// What a run of Earshot measured.
struct EarshotRun {
  double rtf = 0;
  double convolutions = 0;  // per source and block, timed blocks
};

/// Realtime factor of Earshot's Renderer with n moving sources; with
/// `tier` (decoder filters), the Ambisonic tier.
EarshotRun run_earshot(int n, const Budget& budget, const std::shared_ptr<const earshot::hrtf::HrtfSet>& hrtf,
                       const std::vector<std::vector<float>>& loops,
                       const earshot::ambisonics::DecoderFilters* tier = nullptr) {
  earshot::audio::RendererConfig cfg;
  cfg.sample_rate = kRate;
  cfg.block = kBlock;
  cfg.max_sources = std::size_t(n);
  cfg.near_field = budget.near_field;
  const earshot::audio::PreparedHrtf prepared{hrtf, std::make_shared<const earshot::audio::HrtfSpectra>(*hrtf, kBlock)};
  earshot::audio::Renderer r =
      tier ? earshot::audio::Renderer(prepared, cfg,
                                      std::make_unique<earshot::ambisonics::AmbisonicBus>(*tier, kBlock, cfg.max_sources))
           : earshot::audio::Renderer(prepared, cfg);
  const std::vector<Path> path = paths(n);
  std::vector<int> ids;
  std::vector<std::size_t> read(static_cast<std::size_t>(n));
  earshot::audio::SourceState s;
  s.gain = source_gain(n);
  for (int i = 0; i < n; ++i) {
    s.position = path[std::size_t(i)].position(0);
    ids.push_back(r.add_source(s));
    if (ids.back() < 0) throw std::runtime_error("Earshot refused source " + std::to_string(i));
    read[std::size_t(i)] = std::size_t(i) * 977 % kRate;
  }
  std::vector<float> left(kBlock), right(kBlock);
  std::size_t block = 0, convolutions = 0;
  auto step = [&] {
    const double t = budget.still ? 0.0 : double(block * kBlock) / kRate;
    for (int i = 0; i < n; ++i) {
      const auto k = std::size_t(i);
      s.position = path[k].position(t);
      r.set_source(ids[k], s);
      // The next block of the source's loop, in runs up to the loop's end
      // (as an engine streaming a buffer would copy it).
      const std::vector<float>& loop = loops[k % kLoops];
      const std::span<float> in = r.source_input(ids[k]);
      for (std::size_t done = 0; done < in.size();) {
        const std::size_t run = std::min(in.size() - done, loop.size() - read[k]);
        std::copy_n(loop.begin() + static_cast<std::ptrdiff_t>(read[k]), run, in.begin() + static_cast<std::ptrdiff_t>(done));
        done += run;
        read[k] = (read[k] + run) % loop.size();
      }
    }
    r.render(left, right);
    convolutions += r.convolutions();
    ++block;
  };
  for (int b = 0; b < 40; ++b) step();  // warm-up, untimed
  const std::size_t first = block;
  convolutions = 0;
  const double start = cpu_seconds();
  double cpu = 0;
  while (double((block - first) * kBlock) / kRate < budget.seconds || cpu < budget.min_cpu) {
    for (int b = 0; b < 16; ++b) step();
    cpu = cpu_seconds() - start;
  }
  return {double((block - first) * kBlock) / kRate / cpu, double(convolutions) / double((block - first) * std::size_t(n))};
}

/// Realtime factor of OpenAL Soft (HRTF, loopback) with n moving sources.
double run_openal(int n, const Budget& budget, const std::vector<std::vector<float>>& loops, std::string& hrtf_name) {
  earshot::bench::OpenAlReference al({.sample_rate = kRate, .sources = n});
  hrtf_name = al.hrtf_name();
  std::vector<int> buffers;
  for (const auto& l : loops) buffers.push_back(al.add_buffer(l));
  const std::vector<Path> path = paths(n);
  for (int i = 0; i < n; ++i) {
    al.set_source_gain(i, source_gain(n));
    al.set_source_position(i, path[std::size_t(i)].position(0));
    al.play_loop(i, buffers[std::size_t(i) % kLoops], std::size_t(i) * 977 % kRate);
  }
  std::vector<float> left(kBlock), right(kBlock);
  std::size_t block = 0;
  auto step = [&] {
    const double t = budget.still ? 0.0 : double(block * kBlock) / kRate;
    for (int i = 0; i < n; ++i) {
      al.set_source_position(i, path[std::size_t(i)].position(t));
      al.set_source_velocity(i, budget.still ? Vec3{0, 0, 0} : path[std::size_t(i)].velocity(t));
    }
    al.render(left, right);
    ++block;
  };
  for (int b = 0; b < 40; ++b) step();
  const std::size_t first = block;
  const double start = cpu_seconds();
  double cpu = 0;
  while (double((block - first) * kBlock) / kRate < budget.seconds || cpu < budget.min_cpu) {
    for (int b = 0; b < 16; ++b) step();
    cpu = cpu_seconds() - start;
  }
  return double((block - first) * kBlock) / kRate / cpu;
}

/// The source count at realtime factor 1: CPU per second of audio (1/RTF)
/// grows about linearly with N, so interpolate it between the bracketing
/// counts, or extrapolate from the last two when every count is realtime.
std::string sources_per_core(std::vector<int> ns, std::vector<double> rtf) {
  while (!rtf.empty() && rtf.back() <= 0) {  // counts not run
    rtf.pop_back();
    ns.pop_back();
  }
  if (rtf.empty()) return "not run";
  char buf[160];
  if (rtf.front() < 1) {
    std::snprintf(buf, sizeof buf, "< %d (RTF %.2f at %d)", ns.front(), rtf.front(), ns.front());
    return buf;
  }
  for (std::size_t k = 0; k + 1 < ns.size(); ++k) {
    if (rtf[k + 1] >= 1) continue;
    const double c0 = 1 / rtf[k], c1 = 1 / rtf[k + 1];
    const double n = ns[k] + (1 - c0) / (c1 - c0) * (ns[k + 1] - ns[k]);
    std::snprintf(buf, sizeof buf, "%.0f (interpolated between %d and %d)", n, ns[k], ns[k + 1]);
    return buf;
  }
  if (ns.size() < 2) {
    std::snprintf(buf, sizeof buf, "> %d", ns.back());
    return buf;
  }
  const std::size_t k = ns.size() - 2;
  const double c0 = 1 / rtf[k], c1 = 1 / rtf[k + 1];
  const double slope = (c1 - c0) / (ns[k + 1] - ns[k]);
  if (slope <= 0) {
    std::snprintf(buf, sizeof buf, "> %d", ns.back());
    return buf;
  }
  std::snprintf(buf, sizeof buf, "> %d (about %.0f extrapolated)", ns.back(), ns[k + 1] + (1 - c1) / slope);
  return buf;
}

std::string tier_name(int order) { return order == 0 ? "direct" : "ambisonic:" + std::to_string(order); }

/// Every tier and OpenAL Soft, interleaved per source count; one table.
int run_tiers(const std::vector<int>& ns, const std::vector<int>& orders, const Budget& budget, int repeat,
              double stop_below, const std::string& hrtf_path, const std::string& only) {
  try {
    const auto hrtf = std::make_shared<const earshot::hrtf::HrtfSet>(
        hrtf_path.empty() ? earshot::hrtf::HrtfSet::load_default(kRate) : earshot::hrtf::HrtfSet::load(hrtf_path, kRate));
    std::map<int, earshot::ambisonics::DecoderFilters> decoders;  // designed before anything is timed
    for (int o : orders)
      if (o > 0 && !decoders.count(o)) decoders.emplace(o, earshot::ambisonics::design_binaural_decoder(*hrtf, o));
    const auto loops = noise_loops();
    std::string al_hrtf;
    std::vector<std::vector<double>> rtf(orders.size());  // [tier][count], 0: not run
    std::vector<double> oal;
    for (int n : ns) {
      std::vector<double> best(orders.size(), 0.0);
      double best_o = 0;
      for (int k = 0; k < repeat; ++k) {  // interleaved: slow drifts in load hit every renderer alike
        for (std::size_t t = 0; t < orders.size(); ++t) {
          if (only == "openal" || (!rtf[t].empty() && rtf[t].back() < stop_below)) continue;
          const auto* tier = orders[t] > 0 ? &decoders.at(orders[t]) : nullptr;
          best[t] = std::max(best[t], run_earshot(n, budget, hrtf, loops, tier).rtf);
        }
        if (only != "earshot" && (oal.empty() || oal.back() >= stop_below))
          best_o = std::max(best_o, run_openal(n, budget, loops, al_hrtf));
      }
      for (std::size_t t = 0; t < orders.size(); ++t) rtf[t].push_back(best[t]);
      oal.push_back(best_o);
      std::fprintf(stderr, "render_throughput: %d sources done\n", n);
    }
    std::printf("### %s sources by tier, %d Hz, %zu-frame blocks, one thread\n\n", budget.still ? "Still" : "Moving",
                kRate, kBlock);
    std::printf("Earshot: MIT KEMAR, %zu-tap filters (direct); the ambisonic tiers' MagLS decoders from the same set. "
                "OpenAL Soft 1.19 HRTF data set: \"%s\". CPU per source and block in us (best of %d; each >= %.2g s "
                "audio, >= %.2g CPU s); ratio = CPU / OpenAL Soft's CPU.\n\n",
                hrtf->filter_length(), al_hrtf.c_str(), repeat, budget.seconds, budget.min_cpu);
    std::printf("| sources |");
    for (int o : orders) std::printf(" %s us |", tier_name(o).c_str());
    std::printf(" OpenAL Soft us |");
    for (int o : orders) std::printf(" %s / OpenAL |", tier_name(o).c_str());
    std::printf("\n|---:|");
    for (std::size_t t = 0; t < 2 * orders.size() + 1; ++t) std::printf("---:|");
    std::printf("\n");
    const double block_us = 1e6 * double(kBlock) / kRate;
    for (std::size_t k = 0; k < ns.size(); ++k) {
      const auto us = [&](double r) {
        char b[32];
        if (r > 0) std::snprintf(b, sizeof b, "%.2f", block_us / (r * ns[k]));
        return r > 0 ? std::string(b) : std::string("not run");
      };
      std::printf("| %d |", ns[k]);
      for (std::size_t t = 0; t < orders.size(); ++t) std::printf(" %s |", us(rtf[t][k]).c_str());
      std::printf(" %s |", us(oal[k]).c_str());
      for (std::size_t t = 0; t < orders.size(); ++t) {
        if (rtf[t][k] > 0 && oal[k] > 0) std::printf(" **%.2f** |", oal[k] / rtf[t][k]);
        else std::printf(" - |");
      }
      std::printf("\n");
    }
    for (std::size_t t = 0; t < orders.size(); ++t)
      std::printf("\nSources per core at realtime factor 1, %s: %s.", tier_name(orders[t]).c_str(),
                  sources_per_core(ns, rtf[t]).c_str());
    std::printf("\nOpenAL Soft: %s.\n", sources_per_core(ns, oal).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_throughput: %s\n", e.what());
    return 2;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Realtime factor of N moving HRTF sources: Earshot against OpenAL Soft");
  std::vector<int> ns{1, 8, 32, 64, 128, 256};
  std::optional<int> max_sources;
  Budget budget{2.0, 1.0, false};
  int repeat = 3;
  double stop_below = 0.2;
  app.add_option("--sources", ns, "source counts")->delimiter(',')->check(CLI::Range(1, 4096));
  app.add_option("--max-sources", max_sources, "leave out counts above this")->check(CLI::Range(1, 4096));
  app.add_option("--seconds", budget.seconds, "least audio per measurement")->check(CLI::Range(0.01, 600.0));
  app.add_option("--min-cpu", budget.min_cpu, "least CPU seconds per measurement")->check(CLI::Range(0.0, 600.0));
  app.add_option("--repeat", repeat, "measurements per point; the best is kept")->check(CLI::Range(1, 100));
  app.add_flag("--still", budget.still, "sources stay put (the cost without filter updates)");
  app.add_flag("!--no-near-field", budget.near_field, "Earshot without its near field (what it costs)");
  using Blend = earshot::hrtf::HrtfSet::FilterBlend;
  Blend blend = Blend::floored;
  app.add_option("--blend", blend,
                 "Earshot's filter blend: floored (the default), plain (barycentric: what the floor saves), "
                 "nearest (one measurement per ear: what one convolution per ear would cost)")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, Blend>{{"floored", Blend::floored}, {"plain", Blend::plain}, {"nearest", Blend::nearest}}));
  app.add_option("--stop-below", stop_below, "skip larger N for a renderer once its RTF fell below this");
  std::vector<std::string> qualities{"direct"};
  app.add_option("--quality", qualities, "renderer tiers: direct and/or ambisonic:N (N = 1..7)")->delimiter(',');
  std::string only = "both", csv_path, hrtf_path;
  app.add_option("--hrtf", hrtf_path, "Earshot's SOFA set (default: MIT KEMAR); OpenAL Soft keeps its own");
  app.add_option("--csv", csv_path, "also write the table as CSV (for tools/plot_throughput.py)");
  app.add_option("--only", only, "run one renderer (for a profiler)")->check(CLI::IsMember({"both", "earshot", "openal"}));
  CLI11_PARSE(app, argc, argv);
  std::sort(ns.begin(), ns.end());
  ns.erase(std::unique(ns.begin(), ns.end()), ns.end());
  if (max_sources) std::erase_if(ns, [&](int n) { return n > *max_sources; });
  if (ns.empty()) {
    std::fprintf(stderr, "render_throughput: no source counts left\n");
    return 2;
  }
  std::vector<int> orders;  // 0: direct
  for (const std::string& q : qualities) {
    if (q == "direct") {
      orders.push_back(0);
    } else if (q.size() == 11 && q.starts_with("ambisonic:") && q[10] >= '1' && q[10] <= '7') {
      orders.push_back(q[10] - '0');
    } else {
      std::fprintf(stderr, "render_throughput: unknown quality '%s' (direct, ambisonic:1 to ambisonic:7)\n", q.c_str());
      return 2;
    }
  }
  if (orders.size() > 1 || orders.front() != 0) return run_tiers(ns, orders, budget, repeat, stop_below, hrtf_path, only);

  try {
    auto set = std::make_shared<earshot::hrtf::HrtfSet>(
        hrtf_path.empty() ? earshot::hrtf::HrtfSet::load_default(kRate) : earshot::hrtf::HrtfSet::load(hrtf_path, kRate));
    set->set_filter_blend(blend);
    const std::shared_ptr<const earshot::hrtf::HrtfSet> hrtf = std::move(set);
    std::fprintf(stderr, "render_throughput: Earshot's set %s, %zu directions, %zu-tap filters at %d Hz\n",
                 hrtf_path.empty() ? earshot::hrtf::HrtfSet::kDefaultPath : hrtf_path.c_str(), hrtf->measurement_count(),
                 hrtf->filter_length(), kRate);
    const auto loops = noise_loops();
    std::string al_hrtf;
    std::vector<double> ear, oal, conv;  // 0: not run
    for (int n : ns) {
      const bool run_e = only != "openal" && (ear.empty() || ear.back() >= stop_below);
      const bool run_o = only != "earshot" && (oal.empty() || oal.back() >= stop_below);
      double best_e = 0, best_o = 0, conv_e = 0;
      for (int k = 0; k < repeat; ++k) {  // interleaved, so slow drifts in load hit both
        if (run_e) {
          const EarshotRun e = run_earshot(n, budget, hrtf, loops);
          best_e = std::max(best_e, e.rtf);
          conv_e = e.convolutions;  // the same work every time
        }
        if (run_o) best_o = std::max(best_o, run_openal(n, budget, loops, al_hrtf));
      }
      ear.push_back(best_e);
      conv.push_back(conv_e);
      oal.push_back(best_o);
      std::fprintf(stderr, "render_throughput: %d sources done\n", n);
    }

    std::printf("### %s HRTF sources, %d Hz, %zu-frame blocks, one thread\n\n", budget.still ? "Still" : "Moving", kRate,
                kBlock);
    std::printf("Earshot: MIT KEMAR, %zu-tap filters. OpenAL Soft 1.19 HRTF data set: \"%s\". ", hrtf->filter_length(),
                al_hrtf.c_str());
    std::printf("Realtime factor = seconds of audio per CPU second (best of %d; each >= %.2g s audio, >= %.2g CPU s).\n\n",
                repeat, budget.seconds, budget.min_cpu);
    std::printf("| sources | Earshot RTF | OpenAL Soft RTF | Earshot / OpenAL | Earshot us per source-block |"
                " OpenAL us per source-block | Earshot convolutions per source-block |\n|---|---|---|---|---|---|---|\n");
    auto cell = [](double v, const char* fmt) {
      char buf[32];
      if (v > 0) std::snprintf(buf, sizeof buf, fmt, v);
      return v > 0 ? std::string(buf) : std::string("not run");
    };
    const double block_us = 1e6 * double(kBlock) / kRate;
    for (std::size_t k = 0; k < ns.size(); ++k)
      std::printf("| %d | %s | %s | %s | %s | %s | %s |\n", ns[k], cell(ear[k], "%.2f").c_str(), cell(oal[k], "%.2f").c_str(),
                  ear[k] > 0 && oal[k] > 0 ? cell(ear[k] / oal[k], "%.2f").c_str() : "-",
                  cell(ear[k] > 0 ? block_us / (ear[k] * ns[k]) : 0, "%.2f").c_str(),
                  cell(oal[k] > 0 ? block_us / (oal[k] * ns[k]) : 0, "%.2f").c_str(), cell(conv[k], "%.2f").c_str());
    if (!csv_path.empty()) {
      std::FILE* f = std::fopen(csv_path.c_str(), "w");
      if (!f) throw std::runtime_error(csv_path + ": cannot write");
      std::fprintf(f, "sources,moving,earshot_rtf,openal_rtf\n");  // RTF 0: not run
      for (std::size_t k = 0; k < ns.size(); ++k)
        std::fprintf(f, "%d,%d,%.6g,%.6g\n", ns[k], budget.still ? 0 : 1, ear[k], oal[k]);
      if (std::fclose(f) != 0) throw std::runtime_error(csv_path + ": cannot write");
    }
    std::printf("\nSources per core at realtime factor 1: Earshot %s; OpenAL Soft %s.\n",
                sources_per_core(ns, ear).c_str(), sources_per_core(ns, oal).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_throughput: %s\n", e.what());
    return 2;
  }
  return 0;
}
