// Cost of the room reverbs at 48 kHz in 128-frame blocks, as the fraction of
// one core they take in real time ("core_pct": CPU seconds per second of
// audio, in percent). Late reverbs alone and the whole room reverb (input
// filter, early reflections, pre-delay, late reverb), preset "concert-hall".
//
//   reverb_cost [--benchmark_repetitions=5 ...]
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "earshot/audio/reverb_fdn.hpp"
#include "earshot/audio/reverb_schroeder.hpp"
#include "earshot/audio/room_reverb.hpp"

using namespace earshot::audio;

namespace {
constexpr double kFs = 48000.0;
constexpr std::size_t kBlock = 128;

std::vector<float> noise(std::size_t n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.5f, 0.5f);
  std::vector<float> v(n);
  for (auto& x : v) x = u(rng);
  return v;
}

template <class Unit>
void run(benchmark::State& state, Unit& unit) {
  const auto in = noise(kBlock * 64);
  std::vector<float> l(kBlock), r(kBlock);
  std::size_t k = 0;
  for (auto _ : state) {
    unit.process(std::span(in).subspan((k++ % 64) * kBlock, kBlock), l, r);
    benchmark::DoNotOptimize(l.data());
    benchmark::DoNotOptimize(r.data());
  }
  const double audio_s = static_cast<double>(state.iterations()) * kBlock / kFs;
  state.counters["core_pct"] = benchmark::Counter(audio_s / 100.0, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_Fdn(benchmark::State& state) {
  ReverbFdn fdn(kFs, kBlock);
  fdn.update(room_preset("concert-hall"));
  run(state, fdn);
}
void BM_Schroeder(benchmark::State& state) {
  ReverbSchroeder s(kFs, kBlock);
  s.update(room_preset("concert-hall"));
  run(state, s);
}
void BM_RoomReverbFdn(benchmark::State& state) {
  RoomReverb rr(kFs, kBlock, room_preset("concert-hall"), LateReverbType::fdn);
  run(state, rr);
}
void BM_RoomReverbSchroeder(benchmark::State& state) {
  RoomReverb rr(kFs, kBlock, room_preset("concert-hall"), LateReverbType::schroeder);
  run(state, rr);
}
}  // namespace

BENCHMARK(BM_Fdn);
BENCHMARK(BM_Schroeder);
BENCHMARK(BM_RoomReverbFdn);
BENCHMARK(BM_RoomReverbSchroeder);
BENCHMARK_MAIN();
