#include "tracker_state.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace earshot::plugin {
namespace {

template <std::size_t N>
void copy_text(char (&to)[N], const std::string& from) {
  const std::size_t n = std::min(from.size(), N - 1);
  std::memcpy(to, from.data(), n);
  to[n] = '\0';
}

ESuint saturate(std::uint64_t v) {
  return static_cast<ESuint>(std::min<std::uint64_t>(v, std::numeric_limits<ESuint>::max()));
}

}  // namespace

void fill_tracker_state(const tracker::LiveTracker::Status* st, EStrackerstate& out) {
  const ESuint size = out.size;
  out = EStrackerstate{};
  out.size = size;
  if (!st) {
    out.state = ES_TRACKER_NONE;
    copy_text(out.message, "no tracker attached: the head is the host's (esSetHeadPose) or straight ahead");
    return;
  }
  using Link = tracker::LiveTracker::Link;
  out.running = st->running ? ES_TRUE : ES_FALSE;
  out.rate_hz = st->running && std::isfinite(st->rate_hz) ? static_cast<ESfloat>(st->rate_hz) : 0.0f;
  out.frames = saturate(st->camera ? st->frames : st->published);
  out.dropped = saturate(st->dropped);
  copy_text(out.source, st->source);
  for (std::size_t s = 0; s < st->dots.size() && out.dot_count < ES_TRACKER_MAX_DOTS; ++s) {
    const auto& d = st->dots[s];
    if (!d || !std::isfinite(d->x) || !std::isfinite(d->y)) continue;
    EStrackerdot& o = out.dots[out.dot_count++];
    o.x = static_cast<ESfloat>(d->x), o.y = static_cast<ESfloat>(d->y);
    o.size = d->size, o.label = d->label, o.slot = static_cast<ESint>(s);
  }

  const std::string eases = "the head holds, then eases to straight ahead";
  std::string message;
  if (st->ended) {
    out.state = ES_TRACKER_LOST;
    if (!st->error.empty()) message = "tracker stopped: " + st->error + "; " + eases;
    else message = (st->note.empty() ? std::string("the tracker's input ended") : st->note) + "; " + eases;
  } else if (st->link == Link::searching) {
    out.state = ES_TRACKER_SEARCHING;
    message = st->note;
  } else if (st->link == Link::disconnected) {
    out.state = ES_TRACKER_DISCONNECTED;
    message = st->note.empty() ? "the device disconnected; reconnecting" : st->note;
    message += "; " + eases;
  } else {
    switch (st->state) {
      case PoseState::tracking:
      case PoseState::predicted:
        out.state = ES_TRACKER_TRACKING;
        if (st->link == Link::connected) message = st->note;  // e.g. a kernel driver warning
        break;
      case PoseState::lost:
        out.state = ES_TRACKER_LOST;
        message = std::string(st->camera ? "tracking lost (are the four LEDs in the camera's view?)"
                                         : "no pose from " + st->source + " lately") +
                  "; " + eases;
        break;
      case PoseState::searching:
        if (st->link == Link::connected) {
          out.state = ES_TRACKER_CONNECTED;
          message = "connected; no pose yet: turn the four LEDs towards the camera";
        } else {
          out.state = ES_TRACKER_SEARCHING;
          message = "waiting for the first frame from " + st->source;
        }
        break;
    }
  }
  copy_text(out.message, message);
}

void fill_tracker_image(const tracker::Thumbnail* th, int camera_width, int camera_height, EStrackerimage& out) {
  const ESuint size = out.size;
  std::memset(&out, 0, sizeof out);  // the pixels beyond width * height too
  out.size = size;
  out.camera_width = static_cast<ESuint>(std::max(camera_width, 0));
  out.camera_height = static_cast<ESuint>(std::max(camera_height, 0));
  if (!th || th->width <= 0 || th->height <= 0) return;
  const int w = std::min(th->width, ES_TRACKER_IMAGE_MAX_WIDTH), h = std::min(th->height, ES_TRACKER_IMAGE_MAX_HEIGHT);
  static_assert(tracker::Thumbnail::kMaxWidth == ES_TRACKER_IMAGE_MAX_WIDTH &&
                    tracker::Thumbnail::kMaxHeight == ES_TRACKER_IMAGE_MAX_HEIGHT,
                "the C API's picture holds the tracker's thumbnail");
  out.available = ES_TRUE;
  out.width = static_cast<ESuint>(w), out.height = static_cast<ESuint>(h);
  // Rows stay `th->width` apart in the thumbnail and `w` apart here (the same
  // unless a thumbnail ever outgrew the C struct).
  for (int y = 0; y < h; ++y)
    std::memcpy(out.pixels + static_cast<std::size_t>(y) * static_cast<std::size_t>(w),
                th->pixels.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(th->width),
                static_cast<std::size_t>(w));
  out.frame = static_cast<ESuint>(th->frame);  // wraps: a changed number is a new frame
  out.time = std::isfinite(th->t) ? th->t : 0.0;
  for (std::size_t k = 0; k < th->dots.size() && out.dot_count < ES_TRACKER_MAX_DOTS; ++k) {
    const auto& d = th->dots[k];
    if (!d || !std::isfinite(d->x()) || !std::isfinite(d->y())) continue;
    EStrackerimagedot& o = out.dots[out.dot_count++];
    o.x = static_cast<ESfloat>(d->x()), o.y = static_cast<ESfloat>(d->y());
    o.label = th->labelled ? static_cast<ESint>(k) : -1;
    o.slot = static_cast<ESint>(k);
  }
}

}  // namespace earshot::plugin
