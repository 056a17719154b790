// Camera sources without a camera: the simulator (a seeded random walk, with
// optional faults) and the replay of a recorded Dots CSV. Both run paced in
// real time (a frame when its time comes) or as fast as the reader takes them.
#pragma once

#include <chrono>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "earshot/tracker/sim/frame_faults.hpp"
#include "earshot/tracker/core/frame_source.hpp"
#include "earshot/tracker/sim/simulator.hpp"

namespace earshot::tracker {

struct SimSourceConfig {
  /// The simulated head: a seated listener with an occasional look away
  /// (MotionProfile::listener), as a demo's listener would sit; set
  /// `sim.motion = MotionProfile::walk` for the random walk over the box.
  SimulatorConfig sim{.motion = MotionProfile::listener};
  Pacing pacing = Pacing::real_time;
  long frames = -1;  ///< frames before the source ends; -1: never
  std::vector<Fault> faults;
};

class SimSource final : public FrameSource {
 public:
  SimSource(const Camera& cam, const LedModel& model, SimSourceConfig cfg);
  SourceEvent next(std::chrono::milliseconds timeout) override;
  [[nodiscard]] std::string describe() const override { return "sim"; }
  /// Ground truth of the last frame handed out (tests).
  [[nodiscard]] const std::optional<GroundTruth>& truth() const { return truth_; }

 private:
  Simulator sim_;
  SimSourceConfig cfg_;
  long frame_ = 0;
  std::optional<GroundTruth> truth_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// Replays a Dots CSV (frame times from its t_s column). Bad lines throw
/// InputError naming the file, line and field.
class ReplaySource final : public FrameSource {
 public:
  ReplaySource(const std::string& path, Pacing pacing);
  SourceEvent next(std::chrono::milliseconds timeout) override;
  [[nodiscard]] std::string describe() const override { return "replay:" + path_; }

 private:
  std::string path_;
  Pacing pacing_;
  std::ifstream in_;
  std::unique_ptr<DotsCsvReader> reader_;
  std::optional<double> t0_;
  std::chrono::steady_clock::time_point start_;
  std::optional<DotFrame> pending_;
  bool ended_ = false;
};

}  // namespace earshot::tracker
