// Latency of the live tracker: from a camera frame's arrival (the moment the
// source hands it to the tracker thread) to its pose in the PoseSlot, and the
// cost of a reader's load. Frames are simulated in advance (a seeded walk,
// four dots, thesis beacon) and handed over at the Wii Remote's 100 Hz.
//   tracker_latency [--frames N] [--rate HZ]
// Prints a markdown table (p50, p99, max in microseconds). Asserts nothing.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "earshot/tracker/live/live_tracker.hpp"
#include "earshot/tracker/sim/simulator.hpp"

using namespace earshot::tracker;
using earshot::HeadPose;
using earshot::PoseSlot;
using clock_type = std::chrono::steady_clock;

namespace {

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(clock_type::now().time_since_epoch()).count();
}

/// Hands pre-simulated frames over at a fixed rate; records when each was handed over.
class PacedFrames final : public FrameSource {
 public:
  PacedFrames(std::vector<DotFrame> frames, double rate, std::vector<std::atomic<std::int64_t>>& arrival)
      : frames_(std::move(frames)), period_(1.0 / rate), arrival_(arrival) {}
  SourceEvent next(std::chrono::milliseconds) override {
    if (i_ >= frames_.size()) return make_note(SourceNote::Kind::ended, "done");
    std::this_thread::sleep_until(start_ + std::chrono::duration_cast<clock_type::duration>(
                                               std::chrono::duration<double>(static_cast<double>(i_) * period_)));
    CameraFrame f;
    f.dots.t = frames_[i_].t;
    f.dots.slots = frames_[i_].slots;
    arrival_[i_].store(now_ns(), std::memory_order_release);
    ++i_;
    return f;
  }
  [[nodiscard]] std::string describe() const override { return "paced sim"; }

 private:
  std::vector<DotFrame> frames_;
  double period_;
  std::vector<std::atomic<std::int64_t>>& arrival_;
  std::size_t i_ = 0;
  clock_type::time_point start_ = clock_type::now();
};

struct Percentiles {
  double p50, p99, max;
};

Percentiles percentiles(std::vector<double> v) {
  if (v.empty()) return {0, 0, 0};
  std::sort(v.begin(), v.end());
  auto at = [&](double q) { return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))]; };
  return {at(0.50), at(0.99), v.back()};
}

}  // namespace

int main(int argc, char** argv) {
  long frames = 3000;
  double rate = 100.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--frames")) frames = std::atol(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--rate")) rate = std::atof(argv[i + 1]);
  }
  const Camera cam = Camera::with_focal(1280.0);
  SimulatorConfig sc;
  sc.seed = 1;
  sc.rate_hz = rate;
  Simulator sim(cam, LedModel::thesis(), sc);
  std::vector<DotFrame> dots;
  for (long i = 0; i < frames; ++i) dots.push_back(sim.next());

  std::vector<std::atomic<std::int64_t>> arrival(static_cast<std::size_t>(frames));
  std::vector<double> to_slot_us, to_reader_us;
  to_slot_us.reserve(static_cast<std::size_t>(frames));
  to_reader_us.reserve(static_cast<std::size_t>(frames));
  // Reader: loads the slot flat out (a harsher reader than an audio callback),
  // timing every load into a 10 ns histogram.
  std::vector<std::uint64_t> load_hist(100000, 0);
  std::atomic<bool> done{false};
  PoseSlot slot;
  std::thread reader([&] {
    std::uint64_t last = 0;
    while (!done.load(std::memory_order_acquire)) {
      const auto t0 = clock_type::now();
      const HeadPose p = slot.load();
      const auto t1 = clock_type::now();
      const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count();
      ++load_hist[std::min<std::size_t>(static_cast<std::size_t>(ns / 10), load_hist.size() - 1)];
      if (p.sequence == last || p.sequence == 0) continue;
      last = p.sequence;
      const auto k = static_cast<std::size_t>(std::llround(p.t * rate));
      if (k < arrival.size() && p.state != earshot::PoseState::lost)
        to_reader_us.push_back(static_cast<double>(now_ns() - arrival[k].load(std::memory_order_acquire)) * 1e-3);
    }
  });
  {
    LiveTracker tracker(std::make_unique<PacedFrames>(dots, rate, arrival), slot, LiveConfig{},
                        [&](const HeadPose& p) {
                          const auto k = static_cast<std::size_t>(std::llround(p.t * rate));
                          if (k < arrival.size())
                            to_slot_us.push_back(static_cast<double>(now_ns() - arrival[k].load(std::memory_order_acquire)) * 1e-3);
                        });
    while (tracker.running()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  done = true;
  reader.join();

  std::uint64_t loads = 0;
  for (auto c : load_hist) loads += c;
  auto load_q = [&](double q) {
    std::uint64_t acc = 0;
    for (std::size_t i = 0; i < load_hist.size(); ++i)
      if ((acc += load_hist[i]) >= static_cast<std::uint64_t>(q * static_cast<double>(loads))) return static_cast<double>(i) * 0.01;
    return 1000.0;
  };
  const Percentiles s = percentiles(to_slot_us), r = percentiles(to_reader_us);
  std::printf("frames %ld at %.0f Hz, lm + eskf (the live default), thesis beacon; %llu reader loads\n\n", frames, rate,
              static_cast<unsigned long long>(loads));
  std::printf("| measure | p50 | p99 | max |\n|---|---|---|---|\n");
  std::printf("| frame arrival -> pose published in the slot | %.1f us | %.1f us | %.1f us |\n", s.p50, s.p99, s.max);
  std::printf("| frame arrival -> pose seen by a spinning reader | %.1f us | %.1f us | %.1f us |\n", r.p50, r.p99, r.max);
  std::printf("| reader's PoseSlot::load() (incl. ~2 clock reads) | %.2f us | %.2f us | - |\n", load_q(0.5), load_q(0.99));
  return 0;
}
