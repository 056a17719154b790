#include "earshot/tracker/sources/sim_source.hpp"

#include <thread>

#include "earshot/errors.hpp"

namespace earshot::tracker {
namespace {

using clock = std::chrono::steady_clock;

/// Waits until `due` if it comes within `timeout`; false when it does not.
bool wait_until(clock::time_point due, std::chrono::milliseconds timeout) {
  const auto now = clock::now();
  if (due <= now) return true;
  if (due - now > timeout) {
    std::this_thread::sleep_for(timeout);
    return false;
  }
  std::this_thread::sleep_until(due);
  return true;
}

clock::time_point at(clock::time_point start, double t) {
  return start + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(t));
}

}  // namespace

SimSource::SimSource(const Camera& cam, const LedModel& model, SimSourceConfig cfg)
    : sim_(cam, model, cfg.sim), cfg_(std::move(cfg)) {}

SourceEvent SimSource::next(std::chrono::milliseconds timeout) {
  if (cfg_.frames >= 0 && frame_ >= cfg_.frames) return make_note(SourceNote::Kind::ended, "simulation ended");
  const double t = static_cast<double>(frame_) / cfg_.sim.rate_hz;
  if (cfg_.pacing == Pacing::real_time && !wait_until(at(start_, t), timeout)) return make_note(SourceNote::Kind::timeout);
  const long i = frame_++;
  DotFrame f = sim_.next();
  truth_ = f.truth;
  if (silenced(i, cfg_.faults)) return make_note(SourceNote::Kind::timeout, "", t);
  apply_faults(f, i, cfg_.faults);
  CameraFrame out;
  out.dots.t = f.t;
  out.dots.slots = f.slots;  // the live tracker never sees ground truth
  return out;
}

ReplaySource::ReplaySource(const std::string& path, Pacing pacing) : path_(path), pacing_(pacing), in_(path) {
  if (!in_) throw InputError::at(path, 0, "", "cannot open file");
  reader_ = std::make_unique<DotsCsvReader>(in_, path);
}

SourceEvent ReplaySource::next(std::chrono::milliseconds timeout) {
  if (!pending_ && !ended_) {
    pending_ = reader_->next();
    if (!pending_) ended_ = true;
  }
  if (ended_) return make_note(SourceNote::Kind::ended, "end of " + path_);
  if (!t0_) {
    t0_ = pending_->t;
    start_ = clock::now();
  }
  if (pacing_ == Pacing::real_time && !wait_until(at(start_, pending_->t - *t0_), timeout)) return make_note(SourceNote::Kind::timeout);
  CameraFrame out;
  out.dots.t = pending_->t;
  out.dots.slots = pending_->slots;
  pending_.reset();
  return out;
}

}  // namespace earshot::tracker
