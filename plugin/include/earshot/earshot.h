/* Earshot: head-tracked binaural rendering behind a small C API.
 *
 * The shape is OpenAL's: a world (OpenAL's context) at one sample rate and
 * block size; one listener; sources with OpenAL's properties; buffers of
 * mono audio; a room reverb on a send bus; and a head tracker whose pose
 * turns the listener's head. Names follow OpenAL's discipline with an `es`
 * prefix: functions esVerbNoun, enums ES_*, typed setters esSourcef /
 * esSource3f / esSourcefv / esSourcei and matching esGet* getters.
 *
 * Handles are 32-bit names, never pointers. Each carries a generation, so a
 * handle used after its object was deleted (a stale handle) is refused with
 * ES_INVALID_WORLD / ES_INVALID_SOURCE / ES_INVALID_BUFFER, never followed.
 * 0 is never a valid handle.
 *
 * Errors: every call returns an ESenum, ES_OK on success. Nothing is changed
 * by a call that fails. esGetErrorMessage() says, for people, why the last
 * failing call on a world failed (which argument, which value).
 *
 * Commit mode: in ES_IMMEDIATE mode (the default) every change is heard from
 * the next block esRender() starts. In ES_DEFERRED mode changes are collected
 * and become audible together, at one block boundary, after esCommit().
 *
 * Threads (see docs/PLUGIN.md):
 *   - The control thread of a world is the thread that created it, until
 *     another thread calls esSetControlThread(). Every call taking a world
 *     (except those below) must come from it, else ES_WRONG_THREAD.
 *   - esRender() may come from any one thread at a time (the audio thread);
 *     it never blocks, allocates or locks. A second esRender() on the same
 *     world while one is running gets ES_WRONG_THREAD.
 *   - esGetHeadPose() and esGetErrorString() may come from any thread.
 *   - esGetTrackerState() and esGetTrackerImage() come from the control
 *     thread (they may wait a moment for the tracker thread's status or
 *     picture lock; never from the audio thread).
 *   - Source callbacks (ESsourcecallback) run on the audio thread, inside
 *     esRender().
 *   - esDestroyWorld() must come from the control thread; it waits for a
 *     running esRender() on that world to return (from inside esRender, in a
 *     callback: ES_INVALID_OPERATION).
 *
 * Units and frames: OpenAL's world frame (+x right, +y up, -z ahead),
 * metres, seconds, Hz; angles of cones in degrees as OpenAL has them.
 *
 * Linking: link -learshot (pkg-config earshot, CMake find_package(earshot)),
 * or dlopen(ES_LIBRARY_SONAME) ("libearshot.so.1") and call
 * esGetProcTable(ES_ABI_VERSION_MAJOR): the table holds every function
 * below, and its abi_version and size tell a host whether the library it
 * loaded is the one it was built against (docs/PLUGIN.md has an example).
 */
#ifndef EARSHOT_EARSHOT_H
#define EARSHOT_EARSHOT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(EARSHOT_BUILDING_LIBRARY) && defined(__GNUC__)
#define ES_API __attribute__((visibility("default")))
#else
#define ES_API
#endif

/* ABI version of the function table: major in the high 16 bits. A new
 * minor version only appends functions to the table; a new major one breaks
 * it. */
#define ES_ABI_VERSION_MAJOR 1u
#define ES_ABI_VERSION_MINOR 5u /* 1: esGetTrackerState; 2: esWorldHrtf;
                                  * 3: esGetTrackerImage; 4: esAttachTrackerEx;
                                  * 5: Ambisonic fields and the Ambisonic tier */
#define ES_ABI_VERSION ((ES_ABI_VERSION_MAJOR << 16) | ES_ABI_VERSION_MINOR)
/* The file name to dlopen: the soname, which changes with the major version
 * (plugin/CMakeLists.txt reads both from this header, so they cannot drift). */
#define ES_LIBRARY_SONAME "libearshot.so.1"

typedef int32_t ESenum;
typedef int32_t ESint;
typedef uint32_t ESuint;
typedef float ESfloat;
typedef int32_t ESboolean;

typedef uint32_t ESworld;
typedef uint32_t ESsource;
typedef uint32_t ESbuffer;

#define ES_FALSE 0
#define ES_TRUE 1

/* ---- Error codes ------------------------------------------------------ */
#define ES_OK 0
#define ES_INVALID_WORLD 1     /* not a world, or a destroyed one */
#define ES_INVALID_SOURCE 2    /* not a source of this world, or a deleted one */
#define ES_INVALID_BUFFER 3    /* not a buffer of this world, or a deleted one */
#define ES_INVALID_ENUM 4      /* a property that does not exist for this call */
#define ES_INVALID_VALUE 5     /* out of range, NaN, infinite, a null pointer */
#define ES_INVALID_OPERATION 6 /* not now (e.g. deleting a buffer a source plays) */
#define ES_WRONG_THREAD 7      /* not the world's control thread; concurrent esRender */
#define ES_OUT_OF_MEMORY 8     /* or out of slots: max sources, max buffers */
#define ES_HRTF_ERROR 9        /* the SOFA file could not be loaded */
#define ES_TRACKER_ERROR 10    /* the tracker source could not be started */

/* ---- World ------------------------------------------------------------ */
/* Fill with esWorldParamsDefault() and change what you need; `size` lets a
 * newer library read an older caller's struct. */
typedef struct ESworldparams {
  ESuint size;              /* sizeof(ESworldparams) */
  ESuint sample_rate;       /* Hz, 8000..192000; default 48000 */
  ESuint block_size;        /* frames per esRender, 1..8192; default 128 */
  ESuint max_sources;       /* 1..256; default 64 */
  ESuint max_buffers;       /* 1..4096; default 256 */
  ESfloat doppler_factor;   /* >= 0; default 1 (also esDopplerFactor) */
  ESfloat speed_of_sound;   /* m/s, > 0; default 343.3 (also esSpeedOfSound) */
  /* ES_FALSE (default): OpenAL's Doppler, from velocities, as a pitch shift.
   * ES_TRUE: as `earshot render`: each source is delayed by its distance over
   * the speed of sound, so motion itself makes the Doppler shift; velocities
   * are then not used, and the Doppler factor and speed of sound are fixed
   * at creation. */
  ESboolean propagation_delay;
  ESenum late_reverb;       /* ES_REVERB_FDN (default) or ES_REVERB_SCHROEDER */
  ESfloat head_radius_m;    /* 0 (default): the SOFA set's measured ITD; 0.01..0.5:
                             * Woodworth's ITD for a head of this radius */
  const char *hrtf_path;    /* SOFA file; NULL: MIT KEMAR from libmysofa */
} ESworldparams;

#define ES_REVERB_FDN 0x0101
#define ES_REVERB_SCHROEDER 0x0102

/* World-wide properties (esWorldi / esGetWorldi). */
#define ES_COMMIT_MODE 0x4001   /* ES_IMMEDIATE (default) or ES_DEFERRED */
#define ES_IMMEDIATE 0x4002
#define ES_DEFERRED 0x4003
#define ES_SAMPLE_RATE 0x4004   /* get only */
#define ES_BLOCK_SIZE 0x4005    /* get only */
#define ES_MAX_SOURCES 0x4006   /* get only */
#define ES_BLOCKS_RENDERED 0x4007 /* get only: esRender calls that rendered */
/* Head prediction: while a tracker attached with esAttachTracker is
 * tracking, each block turns the head to where the tracked pose, carried on
 * at the filter's velocities, will be when the block is heard: one block
 * plus ES_OUTPUT_LATENCY_US after esRender starts (at most 60 ms ahead;
 * poses from esSetHeadPose and from sources without the filter's velocities
 * are used as they are). */
#define ES_HEAD_PREDICTION 0x4008  /* ES_TRUE (default) or ES_FALSE */
#define ES_OUTPUT_LATENCY_US 0x4009 /* the host's output latency beyond the
                                     * block, microseconds, 0..1000000;
                                     * default 0 */

/* ---- Listener (esListener*) ------------------------------------------- */
#define ES_POSITION 0x1004      /* 3 floats, metres (listener and source) */
#define ES_VELOCITY 0x1006      /* 3 floats, m/s (listener and source) */
#define ES_GAIN 0x100A          /* float >= 0 (listener and source) */
#define ES_ORIENTATION 0x100F   /* listener: 6 floats, "at" then "up" */
#define ES_ORIENTATION_QUAT 0x3100 /* listener: 4 floats w, x, y, z (normalised) */

/* ---- Sources (esSource*) ---------------------------------------------- */
#define ES_SOURCE_RELATIVE 0x0202 /* int ES_TRUE / ES_FALSE */
#define ES_CONE_INNER_ANGLE 0x1001 /* float degrees, 0..360 */
#define ES_CONE_OUTER_ANGLE 0x1002 /* float degrees, 0..360 */
#define ES_PITCH 0x1003          /* float, 1/16..16 */
#define ES_DIRECTION 0x1005      /* 3 floats; zero: omnidirectional */
#define ES_LOOPING 0x1007        /* int ES_TRUE / ES_FALSE */
#define ES_BUFFER 0x1009         /* int: an ESbuffer, 0 for none */
#define ES_MIN_GAIN 0x100D       /* float 0..1 */
#define ES_MAX_GAIN 0x100E       /* float 0..1 */
#define ES_SOURCE_STATE 0x1010   /* get only: ES_INITIAL/PLAYING/PAUSED/STOPPED */
#define ES_REFERENCE_DISTANCE 0x1020 /* float >= 0 */
#define ES_ROLLOFF_FACTOR 0x1021 /* float >= 0 */
#define ES_CONE_OUTER_GAIN 0x1022 /* float 0..1 */
#define ES_MAX_DISTANCE 0x1023   /* float >= 0; default FLT_MAX */
#define ES_SAMPLE_OFFSET 0x1025  /* get only: playback position in buffer frames */
#define ES_DISTANCE_MODEL 0xD000 /* int: one of the models below */
#define ES_REVERB_SEND 0x20001   /* float 0..10: linear gain into the reverb */
#define ES_AIR_ABSORPTION_FACTOR 0x20007 /* float 0..10 (OpenAL's) */

#define ES_INITIAL 0x1011
#define ES_PLAYING 0x1012
#define ES_PAUSED 0x1013
#define ES_STOPPED 0x1014

#define ES_NONE 0
#define ES_INVERSE_DISTANCE 0xD001
#define ES_INVERSE_DISTANCE_CLAMPED 0xD002 /* the default */
#define ES_LINEAR_DISTANCE 0xD003
#define ES_LINEAR_DISTANCE_CLAMPED 0xD004
#define ES_EXPONENT_DISTANCE 0xD005
#define ES_EXPONENT_DISTANCE_CLAMPED 0xD006

/* Audio pulled from the host, on the audio thread inside esRender: write
 * `frames` mono samples at the world's rate to `out`. Pitch and Doppler are
 * not applied to callback audio (the host owns its timeline). Must not
 * block. */
typedef void (*ESsourcecallback)(void *user, float *out, ESuint frames);

/* ---- Reverb (esReverb*) ----------------------------------------------- */
/* The room on the send bus: the thesis's Table 1 parameters, as OpenAL's
 * EFX reverb fields (gains linear, times in seconds). Ranges are EFX's. */
#define ES_REVERB_ENABLED 0x3000        /* int, default ES_FALSE */
#define ES_REVERB_DENSITY 0x0001
#define ES_REVERB_DIFFUSION 0x0002
#define ES_REVERB_GAIN 0x0003
#define ES_REVERB_GAINHF 0x0004
#define ES_REVERB_DECAY_TIME 0x0005      /* Table 1: reverberation decay time */
#define ES_REVERB_DECAY_HFRATIO 0x0006   /* Table 1: frequency decay ratio */
#define ES_REVERB_REFLECTIONS_GAIN 0x0007
#define ES_REVERB_REFLECTIONS_DELAY 0x0008 /* Table 1: early reflections delay */
#define ES_REVERB_LATE_REVERB_GAIN 0x0009  /* Table 1: reverberation level */
#define ES_REVERB_LATE_REVERB_DELAY 0x000A /* Table 1: reverberation delay */
#define ES_REVERB_HFREFERENCE 0x000B
#define ES_REVERB_WET_DB 0x3001           /* Table 1: wet level, dB (-120..20) */
#define ES_REVERB_DRY_DB 0x3002           /* Table 1: dry level, dB (-120..20) */

/* ---- Functions -------------------------------------------------------- */
/* Always callable, any thread. */
ES_API const char *esGetErrorString(ESenum error);
ES_API void esWorldParamsDefault(ESworldparams *params);

/* World life cycle (the calling thread becomes the control thread). */
ES_API ESenum esCreateWorld(const ESworldparams *params, ESworld *world);
ES_API ESenum esDestroyWorld(ESworld world);
ES_API ESenum esSetControlThread(ESworld world);
/* Why the last failing call on this world failed; "" if none failed yet.
 * The text stays valid until the next failing call or esDestroyWorld.
 * Control thread. With world 0 (any thread): why the calling thread's last
 * failing esCreateWorld failed (e.g. the SOFA file's error, naming it). */
ES_API const char *esGetErrorMessage(ESworld world);

ES_API ESenum esWorldi(ESworld world, ESenum param, ESint value);
ES_API ESenum esGetWorldi(ESworld world, ESenum param, ESint *value);
ES_API ESenum esDopplerFactor(ESworld world, ESfloat factor);
ES_API ESenum esSpeedOfSound(ESworld world, ESfloat metres_per_second);
/* Deferred mode: everything changed since the last commit is heard from the
 * same block. In immediate mode a no-op. */
ES_API ESenum esCommit(ESworld world);

ES_API ESenum esListenerf(ESworld world, ESenum param, ESfloat value);
ES_API ESenum esListener3f(ESworld world, ESenum param, ESfloat x, ESfloat y, ESfloat z);
ES_API ESenum esListenerfv(ESworld world, ESenum param, const ESfloat *values);
ES_API ESenum esGetListenerfv(ESworld world, ESenum param, ESfloat *values);

/* Buffers: mono float samples at `sample_rate` (played resampled when it is
 * not the world's). The samples are copied. */
ES_API ESenum esCreateBuffer(ESworld world, const float *samples, ESuint frames, ESuint sample_rate,
                             ESbuffer *buffer);
/* ES_INVALID_OPERATION while a source has the buffer set. */
ES_API ESenum esDeleteBuffer(ESworld world, ESbuffer buffer);

ES_API ESenum esCreateSource(ESworld world, ESsource *source);
ES_API ESenum esDeleteSource(ESworld world, ESsource source);
ES_API ESenum esSourcef(ESworld world, ESsource source, ESenum param, ESfloat value);
ES_API ESenum esSource3f(ESworld world, ESsource source, ESenum param, ESfloat x, ESfloat y, ESfloat z);
ES_API ESenum esSourcefv(ESworld world, ESsource source, ESenum param, const ESfloat *values);
ES_API ESenum esSourcei(ESworld world, ESsource source, ESenum param, ESint value);
ES_API ESenum esGetSourcef(ESworld world, ESsource source, ESenum param, ESfloat *value);
ES_API ESenum esGetSourcefv(ESworld world, ESsource source, ESenum param, ESfloat *values);
ES_API ESenum esGetSourcei(ESworld world, ESsource source, ESenum param, ESint *value);
/* Pull the source's audio from `callback` instead of a buffer (NULL: none). */
ES_API ESenum esSourceCallback(ESworld world, ESsource source, ESsourcecallback callback, void *user);
ES_API ESenum esSourcePlay(ESworld world, ESsource source);  /* from the start */
ES_API ESenum esSourcePause(ESworld world, ESsource source);
ES_API ESenum esSourceStop(ESworld world, ESsource source);
ES_API ESenum esSourceRewind(ESworld world, ESsource source);

/* The room: a preset by name ("generic", "concert-hall", ... see
 * docs/ARCHITECTURE.md "Reverbs and rooms"), then any Table 1 field. */
ES_API ESenum esReverbPreset(ESworld world, const char *name);
ES_API ESenum esReverbf(ESworld world, ESenum param, ESfloat value);
ES_API ESenum esReverbi(ESworld world, ESenum param, ESint value);
ES_API ESenum esGetReverbf(ESworld world, ESenum param, ESfloat *value);

/* Head tracking: start a live tracker on `spec` ("wiimote", "sim",
 * "replay:DOTS.csv", "opentrack[:PORT][@ADDR]", "osc[:PORT][@ADDR]",
 * "webcam[:DEVICE or VIDEO.y4m][,beacon=leds|apriltag][,size_mm=S]...":
 * docs/PLUGIN.md) and let
 * its pose turn and move the head relative to the listener. The pose sources
 * listen on 127.0.0.1 unless "@ADDR" names another IPv4 address (e.g.
 * "osc:9000@0.0.0.0" for every interface: pose packets are unauthenticated,
 * so anyone on that network could turn the head; docs/OSC.md). NULL or ""
 * detaches. The tracker runs on its own thread; esRender reads its newest
 * pose once per block without waiting. */
ES_API ESenum esAttachTracker(ESworld world, const char *spec);
/* The tracker's current pose becomes neutral. */
ES_API ESenum esRecenter(ESworld world);
/* The head pose the last block used (identity without a tracker): position
 * (3 floats, metres) and orientation (4 floats w, x, y, z). Any thread. */
ES_API ESenum esGetHeadPose(ESworld world, ESfloat *position, ESfloat *orientation);
/* A pose from the host's own tracker (or a recording): used until the next
 * one, when no tracker is attached. Goes through the commit mode. */
ES_API ESenum esSetHeadPose(ESworld world, const ESfloat *position, const ESfloat *orientation);

/* ---- Switching the HRTF set while playing (esWorldHrtf, ABI 1.2) ------ */
/* The world renders with the SOFA set at `sofa_path` from now on (NULL: MIT
 * KEMAR from libmysofa). The set is loaded and prepared on the calling
 * thread through the process's shared cache (the first use of a file in a
 * process takes ~0.1 s for a set like KEMAR; later ones are shared). The
 * audio thread then renders the old and the new set side by side for 512
 * frames and crossfades over the next 512: no gap, no click; esRender stays
 * free of locks and allocation. A file that cannot be used: ES_HRTF_ERROR,
 * esGetErrorMessage names it, and the current set plays on. Control thread. */
ES_API ESenum esWorldHrtf(ESworld world, const char *sofa_path);

/* ---- Tracker state (esGetTrackerState, ABI 1.1) ----------------------- */
/* What the attached tracker is doing, for a host's UI: its state, its rate,
 * the dots its camera sees and a message for people. */
#define ES_TRACKER_NONE 0x5000         /* no tracker attached */
#define ES_TRACKER_SEARCHING 0x5001    /* looking for its device (no Wii Remote found yet),
                                        * or waiting for the first frame or packet */
#define ES_TRACKER_CONNECTED 0x5002    /* the device answers, but no pose yet (dots not in view) */
#define ES_TRACKER_TRACKING 0x5003     /* poses from the camera (or a short gap bridged) */
#define ES_TRACKER_LOST 0x5004         /* no pose: the head holds, then eases to straight
                                        * ahead; also after a source ended or failed */
#define ES_TRACKER_DISCONNECTED 0x5005 /* the device went away; reconnecting by itself */

#define ES_TRACKER_MAX_DOTS 4
#define ES_CAMERA_WIDTH 1024  /* the Wii camera's image, pixels: x 0..1023 right */
#define ES_CAMERA_HEIGHT 768  /* y 0..767 down */

typedef struct EStrackerdot {
  ESfloat x, y;  /* camera pixels (+x right, +y down) */
  ESint size;    /* blob size as the camera reports it (Wii: 0..15); -1 unknown */
  ESint label;   /* LED 0..3 the tracker assigned to this dot; -1 unlabelled */
  ESint slot;    /* the camera's slot 0..3 the dot came in */
} EStrackerdot;

typedef struct EStrackerstate {
  ESuint size;           /* set to sizeof(EStrackerstate) before the call */
  ESenum state;          /* ES_TRACKER_* */
  ESboolean running;     /* the tracker thread runs (ES_FALSE: none, or it stopped) */
  ESfloat rate_hz;       /* camera frames (or poses) per second over the last second */
  ESuint frames;         /* camera frames or poses since it was attached */
  ESuint dropped;        /* malformed input dropped (reports, packets, lines) */
  ESuint dot_count;      /* dots in the newest camera frame, 0..4 (0 when stale) */
  EStrackerdot dots[ES_TRACKER_MAX_DOTS];
  char source[64];       /* the spec, e.g. "wiimote", "replay:walk.csv" (cut, NUL-ended) */
  char message[512];     /* for people: what happened and what to do, e.g. how to pair
                          * a Wii Remote; "" when there is nothing to say (NUL-ended) */
} EStrackerstate;

/* Fills `state` (size set by the caller; smaller than this header's struct:
 * ES_INVALID_VALUE). Without a tracker: ES_TRACKER_NONE. Control thread. */
ES_API ESenum esGetTrackerState(ESworld world, EStrackerstate *state);

/* ---- The tracker's picture (esGetTrackerImage, ABI 1.3) --------------- */
/* A camera source that sees a picture (a webcam: "webcam[:DEVICE][,...]")
 * keeps its newest frame small and grey, with the dots it found in it, for
 * a host's camera view. The Wii Remote's camera reports only dots: it, the
 * simulator, a replay and the pose sources have no picture. */
#define ES_TRACKER_IMAGE_MAX_WIDTH 160
#define ES_TRACKER_IMAGE_MAX_HEIGHT 120

typedef struct EStrackerimagedot {
  ESfloat x, y;  /* thumbnail pixels (+x right, +y down; pixel centres at whole
                  * numbers), as detected: before lens undistortion */
  ESint label;   /* model point 0..3 (a tag's corner) when the detector labels
                  * its dots; -1 unlabelled (LEDs: EStrackerstate has the
                  * tracker's labels, in camera pixels) */
  ESint slot;    /* the detector's slot 0..3 */
} EStrackerimagedot;

typedef struct EStrackerimage {
  ESuint size;           /* set to sizeof(EStrackerimage) before the call */
  ESboolean available;   /* ES_TRUE: the fields below hold a picture; ES_FALSE: no
                          * tracker, a source without one, or no frame yet */
  /* The source camera's whole image, pixels: the frame EStrackerstate's dots
   * are in (a UI scales them by its view's size over these). The Wii
   * Remote's 1024 x 768 for the Wii, simulator and replay; a webcam's size
   * as it was opened when attached. 0 x 0 without a tracker, for pose
   * sources (opentrack, OSC) and for a webcam that was not there yet when
   * attached. Set with or without a picture. */
  ESuint camera_width, camera_height;
  ESuint width, height;  /* the thumbnail: the camera's aspect within 160 x 120 */
  ESuint frame;          /* frames the source delivered up to this one (wraps):
                          * a new picture when it changes */
  ESuint dot_count;      /* dots found in this frame, 0..4 */
  double time;           /* the frame's time, seconds on the source's clock */
  EStrackerimagedot dots[ES_TRACKER_MAX_DOTS];
  /* Grey levels 0..255, row after row from the top, `width` bytes apart;
   * width * height of them are set, the rest are 0. */
  uint8_t pixels[ES_TRACKER_IMAGE_MAX_WIDTH * ES_TRACKER_IMAGE_MAX_HEIGHT];
} EStrackerimage;

/* Fills `image` (size set by the caller; smaller than this header's struct
 * or NULL: ES_INVALID_VALUE). Without a tracker, or with one that has no
 * picture: ES_OK with available = ES_FALSE. Copies about 19 kB under the
 * source's picture lock: call it at a UI's frame rate. Control thread. */
ES_API ESenum esGetTrackerImage(ESworld world, EStrackerimage *image);

/* ---- Tracker options (esAttachTrackerEx, ABI 1.4) --------------------- */
/* esAttachTracker with options, given OpenAL's way (alcCreateContext's
 * attribute list): `options` is a list of name/value string pairs ending
 * with a NULL name, e.g.
 *
 *   const char *opts[] = {"send", "osc:127.0.0.1:9000,format=sparta",
 *                         "send", "opentrack", NULL};
 *   esAttachTrackerEx(world, "webcam:0,beacon=apriltag", opts);
 *
 * Names (docs/PLUGIN.md, "Tracker options"):
 *   "send"  send every pose the tracker publishes on to another program:
 *           "osc[:HOST][:PORT][,format=earshot|sparta|iem|iem-ypr][,rate=HZ]"
 *           or "opentrack[:HOST][:PORT][,rate=HZ]" (docs/OSC.md, "Sending
 *           poses"); 127.0.0.1 unless a host is named; at most rate (default
 *           100) poses a second, sent from the tracker's thread without
 *           blocking it. Repeatable.
 * NULL options: as esAttachTracker. An unknown name, a bad value or more
 * than ES_TRACKER_MAX_OPTIONS pairs: ES_INVALID_VALUE (esGetErrorMessage
 * names it) and the current tracker stays; a host that does not resolve:
 * ES_TRACKER_ERROR. Control thread. */
#define ES_TRACKER_MAX_OPTIONS 64
ES_API ESenum esAttachTrackerEx(ESworld world, const char *spec, const char *const *options);

/* One block: block_size frames into left and right. The audio thread. */
ES_API ESenum esRender(ESworld world, float *left, float *right, ESuint frames);

/* ---- Ambisonic sound fields and the Ambisonic tier (ABI 1.5) ---------- */
/* The shape of OpenAL Soft's AL_SOFT_bformat_ex and AL_SOFT_bformat_hoa.
 *
 * A buffer may hold an Ambisonic sound field of order 1..ES_MAX_AMBISONIC_ORDER:
 * (order + 1)^2 channels in a channel layout and a scaling. A source whose
 * buffer (or field callback) is one plays it as a sound field around the
 * listener: a field of plane waves, fixed in the world with its own
 * orientation (ES_ORIENTATION / ES_ORIENTATION_QUAT on the source; default:
 * the field's front is the world's -z), turned by the listener's
 * orientation and the tracked head like every other source, never moved by
 * the listener's position. ES_SOURCE_RELATIVE makes it turn with the head.
 * Its ES_GAIN, ES_MIN_GAIN, ES_MAX_GAIN, ES_PITCH and ES_LOOPING apply as to
 * a point source; position, velocity, distance, cone, Doppler, air
 * absorption and reverb send do not. The field is decoded to the two ears
 * by a binaural decoder designed from the world's HRTF set for its order
 * (MagLS unless ES_AMBISONIC_DECODER says otherwise): designed once per
 * set, rate and order in a process and kept on disk (docs/AMBISONICS.md):
 * the esSourcei(ES_BUFFER) or esSourceAmbisonicCallback that first needs an
 * order may take ~0.3 s, later ones (and later processes) milliseconds. A new HRTF set (esWorldHrtf)
 * fades each field to the new set's decoder as it does the point sources.
 *
 * Conventions: ambiX (ACN channel order, SN3D) is x, y, z = ahead, left, up:
 * the world's -z, -x, +y. Channel n of ACN is degree l, index m with
 * n = l^2 + l + m. */
#define ES_MAX_AMBISONIC_ORDER 7
#define ES_AMBISONIC_LAYOUT_ACN 0x6000   /* ACN order (ambiX): W Y Z X V T R S U ... */
#define ES_AMBISONIC_LAYOUT_FUMA 0x6001  /* Furse-Malham order W X Y Z R S T U V K L M N O P Q
                                          * (orders 1..3) */
#define ES_AMBISONIC_SCALING_SN3D 0x6010 /* ambiX */
#define ES_AMBISONIC_SCALING_N3D 0x6011  /* SN3D x sqrt(2l + 1) */
#define ES_AMBISONIC_SCALING_FUMA 0x6012 /* maxN, W at -3 dB (orders 1..3) */
/* Source, get only (esGetSourcei): the order of the field the source plays;
 * 0 for a point source. */
#define ES_AMBISONIC_ORDER 0x6020
/* ES_ORIENTATION (6 floats "at", "up") and ES_ORIENTATION_QUAT (w, x, y, z)
 * also apply to sources: a field's orientation. */

/* A field's audio pulled from the host, on the audio thread inside
 * esRender: write `frames` frames of each of `channels` = (order + 1)^2
 * channels, planar (channel c at out[c * frames]), ACN order, SN3D. Must not
 * block. */
typedef void (*ESambisoniccallback)(void *user, float *out, ESuint channels, ESuint frames);

/* A buffer of an Ambisonic field: `frames` frames of (order + 1)^2
 * interleaved channels (channel c of frame i at samples[i * channels + c])
 * in `layout` and `scaling`, at `sample_rate` (played resampled when it is
 * not the world's). Converted to ACN/SN3D and copied. FuMa layouts and
 * scalings stop at order 3. */
ES_API ESenum esCreateAmbisonicBuffer(ESworld world, const float *samples, ESuint frames, ESuint sample_rate,
                                      ESuint order, ESenum layout, ESenum scaling, ESbuffer *buffer);
/* Pull the source's field of `order` from `callback` instead of a buffer
 * (NULL: none; the source is then a silent point source). */
ES_API ESenum esSourceAmbisonicCallback(ESworld world, ESsource source, ESuint order, ESambisoniccallback callback,
                                        void *user);

/* The renderer tier (esWorldi / esGetWorldi): ES_QUALITY_DIRECT (default:
 * every point source through the measured HRTFs, its own ITD, near field)
 * or ES_QUALITY_AMBISONIC(N), N = 1..ES_MAX_AMBISONIC_ORDER: each point
 * source keeps its distance gain, air absorption, Doppler and gain, is
 * encoded into an order-N Ambisonic bus, and the bus is decoded once per
 * block: for many sources, at a fraction of the cost (docs/AMBISONICS.md;
 * no near field, the spatial detail of order N). The renderer for the new
 * tier is prepared on the calling thread (its decoder designed or read
 * from the caches) and faded in as esWorldHrtf does (none before the first
 * block). Control thread. */
#define ES_QUALITY 0x400A
#define ES_QUALITY_DIRECT 0x4100
#define ES_QUALITY_AMBISONIC(order) (0x4100 + (order))
/* The binaural decoder of fields and of the Ambisonic tier made from now
 * on: ES_DECODER_MAGLS (default: magnitude least squares above the order's
 * transition, shadow-weighted) or ES_DECODER_LS (least squares throughout). */
#define ES_AMBISONIC_DECODER 0x400B
#define ES_DECODER_MAGLS 0x4110
#define ES_DECODER_LS 0x4111

/* ---- The function table, for hosts that dlopen the library ------------ */
typedef struct ESproctable {
  ESuint abi_version; /* ES_ABI_VERSION of the library */
  ESuint size;        /* sizeof(ESproctable) of the library */
  const char *(*GetErrorString)(ESenum);
  void (*WorldParamsDefault)(ESworldparams *);
  ESenum (*CreateWorld)(const ESworldparams *, ESworld *);
  ESenum (*DestroyWorld)(ESworld);
  ESenum (*SetControlThread)(ESworld);
  const char *(*GetErrorMessage)(ESworld);
  ESenum (*Worldi)(ESworld, ESenum, ESint);
  ESenum (*GetWorldi)(ESworld, ESenum, ESint *);
  ESenum (*DopplerFactor)(ESworld, ESfloat);
  ESenum (*SpeedOfSound)(ESworld, ESfloat);
  ESenum (*Commit)(ESworld);
  ESenum (*Listenerf)(ESworld, ESenum, ESfloat);
  ESenum (*Listener3f)(ESworld, ESenum, ESfloat, ESfloat, ESfloat);
  ESenum (*Listenerfv)(ESworld, ESenum, const ESfloat *);
  ESenum (*GetListenerfv)(ESworld, ESenum, ESfloat *);
  ESenum (*CreateBuffer)(ESworld, const float *, ESuint, ESuint, ESbuffer *);
  ESenum (*DeleteBuffer)(ESworld, ESbuffer);
  ESenum (*CreateSource)(ESworld, ESsource *);
  ESenum (*DeleteSource)(ESworld, ESsource);
  ESenum (*Sourcef)(ESworld, ESsource, ESenum, ESfloat);
  ESenum (*Source3f)(ESworld, ESsource, ESenum, ESfloat, ESfloat, ESfloat);
  ESenum (*Sourcefv)(ESworld, ESsource, ESenum, const ESfloat *);
  ESenum (*Sourcei)(ESworld, ESsource, ESenum, ESint);
  ESenum (*GetSourcef)(ESworld, ESsource, ESenum, ESfloat *);
  ESenum (*GetSourcefv)(ESworld, ESsource, ESenum, ESfloat *);
  ESenum (*GetSourcei)(ESworld, ESsource, ESenum, ESint *);
  ESenum (*SourceCallback)(ESworld, ESsource, ESsourcecallback, void *);
  ESenum (*SourcePlay)(ESworld, ESsource);
  ESenum (*SourcePause)(ESworld, ESsource);
  ESenum (*SourceStop)(ESworld, ESsource);
  ESenum (*SourceRewind)(ESworld, ESsource);
  ESenum (*ReverbPreset)(ESworld, const char *);
  ESenum (*Reverbf)(ESworld, ESenum, ESfloat);
  ESenum (*Reverbi)(ESworld, ESenum, ESint);
  ESenum (*GetReverbf)(ESworld, ESenum, ESfloat *);
  ESenum (*AttachTracker)(ESworld, const char *);
  ESenum (*Recenter)(ESworld);
  ESenum (*GetHeadPose)(ESworld, ESfloat *, ESfloat *);
  ESenum (*SetHeadPose)(ESworld, const ESfloat *, const ESfloat *);
  ESenum (*Render)(ESworld, float *, float *, ESuint);
  /* ABI 1.1 */
  ESenum (*GetTrackerState)(ESworld, EStrackerstate *);
  /* ABI 1.2 */
  ESenum (*WorldHrtf)(ESworld, const char *);
  /* ABI 1.3 */
  ESenum (*GetTrackerImage)(ESworld, EStrackerimage *);
  /* ABI 1.4 */
  ESenum (*AttachTrackerEx)(ESworld, const char *, const char *const *);
  /* ABI 1.5 */
  ESenum (*CreateAmbisonicBuffer)(ESworld, const float *, ESuint, ESuint, ESuint, ESenum, ESenum, ESbuffer *);
  ESenum (*SourceAmbisonicCallback)(ESworld, ESsource, ESuint, ESambisoniccallback, void *);
} ESproctable;

/* The table for ABI major version `abi_major` (pass ES_ABI_VERSION_MAJOR),
 * or NULL when this library does not implement it. The table is constant
 * and lives as long as the library is loaded. */
ES_API const ESproctable *esGetProcTable(ESuint abi_major);
typedef const ESproctable *(*ESgetproctablefn)(ESuint abi_major);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* EARSHOT_EARSHOT_H */
