/* Earshot's OpenAL Soft bridge: head tracking for an application that
 * already renders with OpenAL (with HRTF on), by one call per frame.
 *
 * The application keeps placing its listener as before, but tells the
 * bridge instead of OpenAL (esalBridgeSetListener: the body, or the
 * camera). On every update the bridge reads the newest tracked head pose
 * and sets the current OpenAL context's AL_POSITION and AL_ORIENTATION to
 * the body's pose turned and moved by the head's. Sources, buffers and
 * effects are untouched.
 *
 * Poses come from a live tracker started by the bridge (the same specs as
 * esAttachTracker: "wiimote", "sim", "replay:DOTS.csv", "opentrack[:PORT][@ADDR]",
 * "osc[:PORT][@ADDR]"; UDP inputs listen on 127.0.0.1 unless @ADDR says
 * otherwise) or from the application (esalBridgeSetHeadPose: its own
 * tracker, a recording).
 *
 * Threads: one bridge is used from one thread, the one that owns the
 * OpenAL context (esalBridgeUpdate calls alListenerfv on the current
 * context). The tracker runs on its own thread. Errors are Earshot's ES_*
 * codes (earshot.h).
 */
#ifndef EARSHOT_OPENAL_BRIDGE_H
#define EARSHOT_OPENAL_BRIDGE_H

#include "earshot/earshot.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The bridge is a plain object owned by the application (one per OpenAL
 * context), so it is handed around as an opaque pointer. */
typedef struct ESALbridge ESALbridge;

/* `tracker_spec` NULL or "": no tracker, poses come from esalBridgeSetHeadPose. */
ES_API ESenum esalCreateBridge(const char *tracker_spec, ESALbridge **bridge);
ES_API void esalDestroyBridge(ESALbridge *bridge);
/* The listener as the application would set it: position (3 floats) and
 * OpenAL's orientation (6 floats, "at" then "up"). Default: origin, facing -z. */
ES_API ESenum esalBridgeSetListener(ESALbridge *bridge, const ESfloat *position, const ESfloat *at_up);
/* A head pose (position 3 floats, metres; orientation w, x, y, z) relative
 * to the listener; used when no tracker runs. */
ES_API ESenum esalBridgeSetHeadPose(ESALbridge *bridge, const ESfloat *position, const ESfloat *orientation);
ES_API ESenum esalBridgeRecenter(ESALbridge *bridge);
/* Applies listener x head pose to the current OpenAL context: ES_OK, or
 * ES_INVALID_OPERATION when there is no current context or OpenAL refused. */
ES_API ESenum esalBridgeUpdate(ESALbridge *bridge);

#ifdef __cplusplus
}
#endif

#endif
