#include "earshot/tracker/live/live_tracker.hpp"

#include <chrono>
#include <cmath>
#include <exception>

namespace earshot::tracker {
namespace detail {  // named, not anonymous: LiveTracker::Loop holds one

using Clock = std::chrono::steady_clock;

/// Events per second over the last second, from their wall-clock times (a
/// ring big enough for any camera or pose stream this tracker reads).
class RateMeter {
 public:
  void add(Clock::time_point t) {
    times_[head_] = t;
    head_ = (head_ + 1) % times_.size();
    if (count_ < times_.size()) ++count_;
  }
  [[nodiscard]] double per_second(Clock::time_point now) const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < count_; ++i) {
      const auto t = times_[(head_ + times_.size() - 1 - i) % times_.size()];
      if (now - t > std::chrono::seconds(1)) break;
      ++n;
    }
    if (n == times_.size()) {  // the ring is shorter than a second: rate from its span
      const double span = std::chrono::duration<double>(now - times_[head_]).count();
      return span > 0.0 ? static_cast<double>(n) / span : 0.0;
    }
    return static_cast<double>(n);
  }

 private:
  std::array<Clock::time_point, 1024> times_{};
  std::size_t head_ = 0, count_ = 0;
};

}  // namespace detail

namespace {

using detail::RateMeter;
constexpr auto kStaleDots = std::chrono::milliseconds(300);

}  // namespace

LiveTracker::LiveTracker(std::unique_ptr<FrameSource> source, PoseSlot& slot, LiveConfig cfg,
                         PoseCallback on_pose, FrameCallback on_frame)
    : source_(std::move(source)),
      slot_(slot),
      keep_running_after_end_(cfg.keep_running_after_end),
      pipeline_(with_source_model(cfg, *source_)),
      on_pose_(std::move(on_pose)),
      on_frame_(std::move(on_frame)),
      senders_(cfg.send) {
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

/// The tracker thread's own bookkeeping between events.
struct LiveTracker::Loop {
  // Notes carry no time: estimate it on the source clock from the last event.
  double last_t = 0.0;
  Clock::time_point last_wall = Clock::now();
  std::string note, error;
  Link link = Link::unknown;
  bool camera = false;
  RateMeter rate;
  std::array<std::optional<Dot>, kSlots> dots;
  Clock::time_point last_frame_wall{};
};

void LiveTracker::process(const SourceEvent& e, double now) {
  const auto pose = pipeline_.process(e, now);
  if (!pose) return;
  if (slot_.publish(*pose)) {
    const HeadPose published = slot_.load();
    senders_.offer(published, Clock::now());
    if (on_pose_) on_pose_(published);
  }
  if (!on_frame_ || std::holds_alternative<SourceNote>(e)) return;
  FrameRow row{*pose, std::nullopt};
  const TrackResult& tr = pipeline_.last_track();
  if (const auto* f = std::get_if<CameraFrame>(&e); f && tr.t == f->dots.t && tr.has_pose) row.camera = tr.pose;
  on_frame_(row);
}

void LiveTracker::update_status(Loop& l, Clock::time_point wall) {
  if (wall - l.last_frame_wall > kStaleDots) l.dots = {};
  std::lock_guard lock(status_mutex_);
  status_.state = pipeline_.state();
  status_.frames = pipeline_.counters().frames;
  status_.published = pipeline_.counters().poses;
  status_.rejected_dots = pipeline_.counters().rejected_dots;
  status_.dropped = source_->dropped();
  status_.note = l.note;
  status_.link = l.link;
  status_.camera = l.camera;
  status_.rate_hz = l.rate.per_second(wall);
  status_.dots = l.dots;
}

bool LiveTracker::handle(Loop& l, const SourceEvent& e) {
  const auto wall = Clock::now();
  if (recenter_.exchange(false, std::memory_order_relaxed)) pipeline_.request_recenter();
  double now = l.last_t + std::chrono::duration<double>(wall - l.last_wall).count();
  bool ended = false;
  const auto* frame = std::get_if<CameraFrame>(&e);
  if (frame) now = frame->dots.t;
  if (const auto* p = std::get_if<HeadPose>(&e)) {
    now = p->t;
    l.rate.add(wall);
  }
  if (const auto* n = std::get_if<SourceNote>(&e)) {
    if (n->kind != SourceNote::Kind::timeout) l.note = n->message;
    if (n->t) now = *n->t;
    ended = n->kind == SourceNote::Kind::ended;
    note_link(l, *n);
  }
  if (std::isfinite(now) && now >= l.last_t) {
    l.last_t = now;
    l.last_wall = wall;
  }
  process(e, l.last_t);
  if (frame) show_dots(l, *frame, wall);
  update_status(l, wall);
  return !ended;
}

void LiveTracker::note_link(Loop& l, const SourceNote& n) {
  if (n.kind == SourceNote::Kind::connected) {
    l.link = Link::connected;
    if (const auto cam = source_->camera()) pipeline_.use_camera(*cam, source_->model());
  }
  if (n.kind == SourceNote::Kind::searching) l.link = Link::searching;
  if (n.kind == SourceNote::Kind::disconnected) l.link = Link::disconnected;
  if (n.kind == SourceNote::Kind::disconnected || n.kind == SourceNote::Kind::searching ||
      n.kind == SourceNote::Kind::ended)
    l.dots = {};
}

void LiveTracker::show_dots(Loop& l, const CameraFrame& frame, Clock::time_point wall) {
  l.camera = true;
  l.rate.add(wall);
  l.last_frame_wall = wall;
  // The labels belong to this frame only if the pipeline tracked it.
  const TrackResult& tr = pipeline_.last_track();
  const bool labelled = tr.t == frame.dots.t;
  for (std::size_t s = 0; s < kSlots; ++s) {
    l.dots[s].reset();
    if (!frame.dots.slots[s]) continue;
    const Vec2& px = *frame.dots.slots[s];
    l.dots[s] = Dot{px.x(), px.y(), frame.dot_size[s], labelled ? tr.slot_led[s] : -1};
  }
}

void LiveTracker::run(std::stop_token stop) {
  Loop l;
  try {
    while (!stop.stop_requested())
      if (!handle(l, source_->next(std::chrono::milliseconds(20)))) break;
  } catch (const std::exception& ex) {
    l.error = ex.what();
  }
  {
    std::lock_guard lock(status_mutex_);
    status_.ended = true;
    status_.error = l.error;
    status_.dots = {};
  }
  // Playing on: the pose the source left holds, then eases to neutral.
  while (keep_running_after_end_ && !stop.stop_requested()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const auto wall = Clock::now();
    l.last_t += std::chrono::duration<double>(wall - l.last_wall).count();
    l.last_wall = wall;
    try {
      process(make_note(SourceNote::Kind::timeout), l.last_t);
    } catch (const std::exception&) {
      break;  // the pipeline never throws on a note; nothing more to publish if it did
    }
    l.dots = {};
    update_status(l, wall);
  }
  std::lock_guard lock(status_mutex_);
  status_.running = false;
  status_.state = pipeline_.state();
  status_.rate_hz = 0.0;
  running_.store(false, std::memory_order_release);
}

}  // namespace earshot::tracker
