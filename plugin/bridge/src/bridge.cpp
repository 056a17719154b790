// The OpenAL bridge: listener x tracked head pose onto the current context.
#include <AL/al.h>
#include <AL/alc.h>

#include <exception>
#include <memory>
#include <new>

#include "earshot/earshot_openal_bridge.h"
#include "earshot/geometry.hpp"
#include "earshot/head/head_reader.hpp"
#include "earshot/head/tracked_head.hpp"
#include "earshot/pose_slot.hpp"
#include "openal_latency.hpp"

using earshot::Quat;
using earshot::Vec3;

struct ESALbridge {
  earshot::PoseSlot slot;  // the tracker's; outlives it
  std::unique_ptr<earshot::head::TrackedHead> tracker;
  earshot::head::HeadReader reader;
  earshot::HeadPose listener;  // the application's (esalBridgeSetListener)
  earshot::HeadPose head;      // the application's own head pose, without a tracker
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
      b->tracker = std::make_unique<earshot::head::TrackedHead>(spec, b->slot);
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
  b->listener.position = {position[0], position[1], position[2]};
  b->listener.orientation = *q;
  return ES_OK;
}

ES_API ESenum esalBridgeSetHeadPose(ESALbridge* b, const ESfloat* position, const ESfloat* orientation) {
  if (!b || !position || !orientation || !finite3(position)) return ES_INVALID_VALUE;
  const auto q = earshot::normalised(Quat{orientation[0], orientation[1], orientation[2], orientation[3]});
  if (!q) return ES_INVALID_VALUE;
  b->head.position = {position[0], position[1], position[2]};
  b->head.orientation = *q;
  return ES_OK;
}

ES_API ESenum esalBridgeRecenter(ESALbridge* b) {
  if (!b) return ES_INVALID_VALUE;
  if (b->tracker) b->tracker->recenter();
  return ES_OK;
}

ES_API ESenum esalBridgeUpdate(ESALbridge* b) {
  if (!b) return ES_INVALID_VALUE;
  ALCcontext* ctx = alcGetCurrentContext();
  if (b->tracker) {
    // The tracked head as the next mix will be heard (the device's latency ahead).
    const earshot::head::HeadTiming timing{.predict = true,
                                           .lead_s = earshot::openal::output_latency_s(ctx ? alcGetContextsDevice(ctx) : nullptr)};
    b->head = b->reader.read(b->slot, timing);
  }
  if (!ctx) return ES_INVALID_OPERATION;
  const earshot::HeadPose heard = earshot::head::compose(b->listener, b->head);
  const Vec3 at = earshot::rotate(heard.orientation, {0, 0, -1}), up = earshot::rotate(heard.orientation, {0, 1, 0});
  const ALfloat pos[3] = {static_cast<ALfloat>(heard.position[0]), static_cast<ALfloat>(heard.position[1]),
                          static_cast<ALfloat>(heard.position[2])};
  const ALfloat ori[6] = {static_cast<ALfloat>(at[0]), static_cast<ALfloat>(at[1]), static_cast<ALfloat>(at[2]),
                          static_cast<ALfloat>(up[0]), static_cast<ALfloat>(up[1]), static_cast<ALfloat>(up[2])};
  (void)alGetError();
  alListenerfv(AL_POSITION, pos);
  alListenerfv(AL_ORIENTATION, ori);
  return alGetError() == AL_NO_ERROR ? ES_OK : ES_INVALID_OPERATION;
}

}  // extern "C"
