// The OpenAL bridge: listener x tracked head pose onto the current context.
#include <AL/al.h>
#include <AL/alc.h>

#include <exception>
#include <memory>
#include <new>

#include "earshot/earshot_openal_bridge.h"
#include "earshot/pose_slot.hpp"
#include "earshot/tracker/live/live_tracker.hpp"
#include "earshot/geometry.hpp"
#include "earshot/tracker/live/source_spec.hpp"

using earshot::Quat;
using earshot::Vec3;

struct ESALbridge {
  earshot::PoseSlot slot;  // the tracker's
  std::unique_ptr<earshot::tracker::LiveTracker> tracker;
  Vec3 listener_position{0, 0, 0};
  Quat listener_orientation{1, 0, 0, 0};
  Vec3 head_position{0, 0, 0};
  Quat head_orientation{1, 0, 0, 0};
};

namespace {
bool finite3(const ESfloat* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
}  // namespace

extern "C" {

ES_API ESenum esalCreateBridge(const char* spec, ESALbridge** out) {
  if (!out) return ES_INVALID_VALUE;
  *out = nullptr;
  try {
    auto b = std::make_unique<ESALbridge>();
    if (spec && *spec) {
      earshot::tracker::SourceOptions source;
      source.wait_for_remote = true;  // no remote yet: the application plays on
      b->tracker = std::make_unique<earshot::tracker::LiveTracker>(
          earshot::tracker::make_frame_source(earshot::tracker::parse_source_spec(spec, "tracker"), source), b->slot);
    }
    *out = b.release();  // owned by the application until esalDestroyBridge
    return ES_OK;
  } catch (const std::bad_alloc&) {
    return ES_OUT_OF_MEMORY;
  } catch (const std::exception&) {
    return ES_TRACKER_ERROR;
  }
}

ES_API void esalDestroyBridge(ESALbridge* b) { std::unique_ptr<ESALbridge> owned(b); }

ES_API ESenum esalBridgeSetListener(ESALbridge* b, const ESfloat* position, const ESfloat* at_up) {
  if (!b || !position || !at_up || !finite3(position)) return ES_INVALID_VALUE;
  const auto q = earshot::quat_from_at_up(Vec3{at_up[0], at_up[1], at_up[2]}, Vec3{at_up[3], at_up[4], at_up[5]});
  if (!q) return ES_INVALID_VALUE;
  b->listener_position = {position[0], position[1], position[2]};
  b->listener_orientation = *q;
  return ES_OK;
}

ES_API ESenum esalBridgeSetHeadPose(ESALbridge* b, const ESfloat* position, const ESfloat* orientation) {
  if (!b || !position || !orientation || !finite3(position)) return ES_INVALID_VALUE;
  const auto q = earshot::normalised(Quat{orientation[0], orientation[1], orientation[2], orientation[3]});
  if (!q) return ES_INVALID_VALUE;
  b->head_position = {position[0], position[1], position[2]};
  b->head_orientation = *q;
  return ES_OK;
}

ES_API ESenum esalBridgeRecenter(ESALbridge* b) {
  if (!b) return ES_INVALID_VALUE;
  if (b->tracker) b->tracker->recenter();
  return ES_OK;
}

ES_API ESenum esalBridgeUpdate(ESALbridge* b) {
  if (!b) return ES_INVALID_VALUE;
  if (b->tracker) {
    if (auto p = b->slot.try_load()) {
      b->head_position = p->position;
      b->head_orientation = p->orientation;
    }
  }
  if (!alcGetCurrentContext()) return ES_INVALID_OPERATION;
  const Quat q = earshot::multiply(b->listener_orientation, b->head_orientation);
  const Vec3 offset = earshot::rotate(b->listener_orientation, b->head_position);
  const Vec3 at = earshot::rotate(q, {0, 0, -1}), up = earshot::rotate(q, {0, 1, 0});
  const ALfloat pos[3] = {static_cast<ALfloat>(b->listener_position[0] + offset[0]),
                          static_cast<ALfloat>(b->listener_position[1] + offset[1]),
                          static_cast<ALfloat>(b->listener_position[2] + offset[2])};
  const ALfloat ori[6] = {static_cast<ALfloat>(at[0]), static_cast<ALfloat>(at[1]), static_cast<ALfloat>(at[2]),
                          static_cast<ALfloat>(up[0]), static_cast<ALfloat>(up[1]), static_cast<ALfloat>(up[2])};
  (void)alGetError();
  alListenerfv(AL_POSITION, pos);
  alListenerfv(AL_ORIENTATION, ori);
  return alGetError() == AL_NO_ERROR ? ES_OK : ES_INVALID_OPERATION;
}

}  // extern "C"
