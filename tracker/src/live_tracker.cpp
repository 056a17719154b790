#include "earshot/tracker/live_tracker.hpp"

#include <chrono>
#include <cmath>
#include <exception>

namespace earshot::tracker {

LiveTracker::LiveTracker(std::unique_ptr<FrameSource> source, PoseSlot& slot, LiveConfig cfg,
                         PoseCallback on_pose)
    : source_(std::move(source)), slot_(slot), pipeline_(cfg), on_pose_(std::move(on_pose)) {
  status_.source = source_->describe();
  thread_ = std::jthread([this](std::stop_token st) { run(st); });
}

LiveTracker::~LiveTracker() { stop(); }

void LiveTracker::stop() {
  if (thread_.joinable()) {
    thread_.request_stop();
    thread_.join();
  }
}

LiveTracker::Status LiveTracker::status() const {
  std::lock_guard lock(status_mutex_);
  return status_;
}

void LiveTracker::run(std::stop_token stop) {
  using clock = std::chrono::steady_clock;
  // Notes carry no time: estimate it on the source clock from the last event.
  double last_t = 0.0;
  auto last_wall = clock::now();
  std::string note, error;
  try {
    while (!stop.stop_requested()) {
      const SourceEvent e = source_->next(std::chrono::milliseconds(20));
      const auto wall = clock::now();
      if (recenter_.exchange(false, std::memory_order_relaxed)) pipeline_.request_recenter();
      double now = last_t + std::chrono::duration<double>(wall - last_wall).count();
      bool ended = false;
      if (const auto* f = std::get_if<CameraFrame>(&e)) now = f->dots.t;
      if (const auto* p = std::get_if<DirectPose>(&e)) now = p->t;
      if (const auto* n = std::get_if<SourceNote>(&e)) {
        if (n->kind != SourceNote::Kind::timeout) note = n->message;
        if (n->t) now = *n->t;
        ended = n->kind == SourceNote::Kind::ended;
      }
      if (std::isfinite(now) && now >= last_t) {
        last_t = now;
        last_wall = wall;
      }
      if (const auto pose = pipeline_.process(e, last_t)) {
        if (slot_.publish(*pose) && on_pose_) on_pose_(slot_.load());
      }
      {
        std::lock_guard lock(status_mutex_);
        status_.state = pipeline_.state();
        status_.frames = pipeline_.counters().frames;
        status_.published = pipeline_.counters().poses;
        status_.rejected_dots = pipeline_.counters().rejected_dots;
        status_.dropped = source_->dropped();
        status_.note = note;
      }
      if (ended) break;
    }
  } catch (const std::exception& ex) {
    error = ex.what();
  }
  std::lock_guard lock(status_mutex_);
  status_.running = false;
  status_.error = error;
  status_.state = pipeline_.state();
  running_.store(false, std::memory_order_release);
}

}  // namespace earshot::tracker
