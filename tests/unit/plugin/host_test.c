/* The plugin from a C host: loads libearshot with dlopen (this program does
 * not link it), renders the scene of host_vs_render.cmake through the
 * function table and compares it with the same scene rendered by
 * `earshot render`: interaural level and time differences (ILD, ITD) per
 * 100 ms window, and the largest sample difference.
 *
 *   plugin_host_test inputs DIR                  writes DIR/a.wav, DIR/b.wav (noise)
 *   plugin_host_test compare LIB DIR REF.wav     renders, compares, exit 0 when the cues match
 */
#include <dlfcn.h>
#include <math.h>
#include <sndfile.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "earshot/earshot.h"

#define RATE 48000
#define FRAMES RATE /* one second */
#define BLOCK 128
#define WINDOW 4800 /* 100 ms */

static float a_in[FRAMES], b_in[FRAMES];
static float ref_l[FRAMES], ref_r[FRAMES], out_l[FRAMES + BLOCK], out_r[FRAMES + BLOCK];

static void noise(float *x, unsigned seed) {
  unsigned s = seed;
  for (int i = 0; i < FRAMES; i++) {
    s = s * 1664525u + 1013904223u;
    x[i] = 0.3f * ((float)(s >> 8) / 8388608.0f - 1.0f);
  }
}

static int write_mono(const char *path, const float *x) {
  SF_INFO info;
  memset(&info, 0, sizeof info);
  info.samplerate = RATE;
  info.channels = 1;
  info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
  SNDFILE *f = sf_open(path, SFM_WRITE, &info);
  if (!f) return 1;
  sf_count_t n = sf_writef_float(f, x, FRAMES);
  sf_close(f);
  return n == FRAMES ? 0 : 1;
}

static int read_mono(const char *path, float *x) {
  SF_INFO info;
  memset(&info, 0, sizeof info);
  SNDFILE *f = sf_open(path, SFM_READ, &info);
  if (!f || info.channels != 1) return 1;
  sf_count_t n = sf_readf_float(f, x, FRAMES);
  sf_close(f);
  return n == FRAMES ? 0 : 1;
}

static int read_stereo(const char *path, float *l, float *r) {
  static float inter[2 * FRAMES];
  SF_INFO info;
  memset(&info, 0, sizeof info);
  SNDFILE *f = sf_open(path, SFM_READ, &info);
  if (!f || info.channels != 2 || info.samplerate != RATE) return 1;
  sf_count_t n = sf_readf_float(f, inter, FRAMES);
  sf_close(f);
  for (sf_count_t i = 0; i < n; i++) {
    l[i] = inter[2 * i];
    r[i] = inter[2 * i + 1];
  }
  return n == FRAMES ? 0 : 1;
}

/* Broadband ILD, dB (left over right). */
static double ild_db(const float *l, const float *r, int n) {
  double el = 1e-20, er = 1e-20;
  for (int i = 0; i < n; i++) {
    el += (double)l[i] * l[i];
    er += (double)r[i] * r[i];
  }
  return 10.0 * log10(el / er);
}

/* ITD in seconds (positive: the left ear leads), cross-correlation peak
 * within +-1 ms, refined by a parabola through the peak and its neighbours. */
static double itd_s(const float *l, const float *r, int n) {
  enum { MAX_LAG = 48 };
  double c[2 * MAX_LAG + 1];
  int best = 0;
  for (int k = -MAX_LAG; k <= MAX_LAG; k++) {
    double s = 0.0;
    for (int i = MAX_LAG; i < n - MAX_LAG; i++) s += (double)l[i] * r[i + k];
    c[k + MAX_LAG] = s;
    if (s > c[best]) best = k + MAX_LAG;
  }
  double frac = 0.0;
  if (best > 0 && best < 2 * MAX_LAG) {
    double y0 = c[best - 1], y1 = c[best], y2 = c[best + 1], d = y0 - 2 * y1 + y2;
    if (d != 0.0) frac = 0.5 * (y0 - y2) / d;
  }
  return ((best - MAX_LAG) + frac) / RATE;
}

static const ESproctable *load(const char *path) {
  void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    fprintf(stderr, "dlopen %s: %s\n", path, dlerror());
    return NULL;
  }
  ESgetproctablefn get = NULL;
  *(void **)(&get) = dlsym(lib, "esGetProcTable"); /* POSIX's way past ISO C's object/function split */
  if (!get) return NULL;
  const ESproctable *es = get(ES_ABI_VERSION_MAJOR);
  if (!es || (es->abi_version >> 16) != ES_ABI_VERSION_MAJOR || es->size < sizeof(ESproctable)) {
    fprintf(stderr, "%s: not Earshot ABI %u\n", path, ES_ABI_VERSION_MAJOR);
    return NULL;
  }
  if (get(ES_ABI_VERSION_MAJOR + 1) != NULL) {
    fprintf(stderr, "esGetProcTable answers an ABI it does not have\n");
    return NULL;
  }
  return es;
}

#define CHECK(call)                                                                   \
  do {                                                                                \
    ESenum e_ = (call);                                                               \
    if (e_ != ES_OK) {                                                                \
      fprintf(stderr, "%s: %s (%s)\n", #call, es->GetErrorString(e_), es->GetErrorMessage(world)); \
      return 1;                                                                       \
    }                                                                                 \
  } while (0)

/* The scene of host_vs_render.cmake, through the API. */
static int render_plugin(const ESproctable *es) {
  ESworldparams p;
  ESworld world = 0;
  ESbuffer ba, bb;
  ESsource sa, sb;
  es->WorldParamsDefault(&p);
  p.propagation_delay = ES_TRUE; /* as earshot render */
  CHECK(es->CreateWorld(&p, &world));
  CHECK(es->Worldi(world, ES_COMMIT_MODE, ES_DEFERRED));
  {
    const double yaw = 20.0 * 3.14159265358979323846 / 180.0; /* listener yaw_deg 20 */
    const ESfloat q[4] = {(ESfloat)cos(yaw / 2), 0.0f, (ESfloat)sin(yaw / 2), 0.0f};
    CHECK(es->Listenerfv(world, ES_ORIENTATION_QUAT, q));
  }
  CHECK(es->ReverbPreset(world, "living-room"));
  CHECK(es->Reverbi(world, ES_REVERB_ENABLED, ES_TRUE));
  CHECK(es->CreateBuffer(world, a_in, FRAMES, RATE, &ba));
  CHECK(es->CreateBuffer(world, b_in, FRAMES, RATE, &bb));
  CHECK(es->CreateSource(world, &sa));
  CHECK(es->Sourcei(world, sa, ES_BUFFER, (ESint)ba));
  CHECK(es->Source3f(world, sa, ES_POSITION, -1.0f, 0.0f, -1.0f));
  CHECK(es->Sourcef(world, sa, ES_REVERB_SEND, (ESfloat)pow(10.0, -10.0 / 20.0)));
  CHECK(es->CreateSource(world, &sb));
  CHECK(es->Sourcei(world, sb, ES_BUFFER, (ESint)bb));
  CHECK(es->Source3f(world, sb, ES_POSITION, 2.0f, 0.0f, 0.5f));
  CHECK(es->Sourcef(world, sb, ES_GAIN, (ESfloat)pow(10.0, -6.0 / 20.0)));
  CHECK(es->SourcePlay(world, sa));
  CHECK(es->SourcePlay(world, sb));
  CHECK(es->Commit(world));
  for (int done = 0; done < FRAMES; done += BLOCK) CHECK(es->Render(world, out_l + done, out_r + done, BLOCK));
  { /* ABI 1.1: the tracker's state through the table, from C */
    EStrackerstate ts;
    memset(&ts, 0, sizeof ts);
    ts.size = sizeof ts;
    CHECK(es->GetTrackerState(world, &ts));
    if (ts.state != ES_TRACKER_NONE || ts.dot_count != 0 || ts.running != ES_FALSE) {
      fprintf(stderr, "a world without a tracker reports state 0x%x, %u dots\n", (unsigned)ts.state, ts.dot_count);
      return 1;
    }
    ts.size = 4;
    if (es->GetTrackerState(world, &ts) != ES_INVALID_VALUE || es->GetTrackerState(world, NULL) != ES_INVALID_VALUE) {
      fprintf(stderr, "esGetTrackerState takes a bad size or NULL\n");
      return 1;
    }
  }
  CHECK(es->DestroyWorld(world));
  if (es->Render(world, out_l, out_r, BLOCK) != ES_INVALID_WORLD) {
    fprintf(stderr, "a destroyed world still renders\n");
    return 1;
  }
  {
    EStrackerstate ts;
    ts.size = sizeof ts;
    if (es->GetTrackerState(world, &ts) != ES_INVALID_WORLD) {
      fprintf(stderr, "a destroyed world still reports its tracker\n");
      return 1;
    }
  }
  return 0;
}

int main(int argc, char **argv) {
  noise(a_in, 1);
  noise(b_in, 2);
  if (argc == 3 && strcmp(argv[1], "inputs") == 0) {
    char path[4096];
    snprintf(path, sizeof path, "%s/a.wav", argv[2]);
    if (write_mono(path, a_in)) return 1;
    snprintf(path, sizeof path, "%s/b.wav", argv[2]);
    return write_mono(path, b_in);
  }
  if (argc != 5 || strcmp(argv[1], "compare") != 0) {
    fprintf(stderr, "usage: %s inputs DIR | compare LIB DIR REF.wav\n", argv[0]);
    return 2;
  }
  char path[4096];
  snprintf(path, sizeof path, "%s/a.wav", argv[3]);
  if (read_mono(path, a_in)) return 1;
  snprintf(path, sizeof path, "%s/b.wav", argv[3]);
  if (read_mono(path, b_in)) return 1;
  if (read_stereo(argv[4], ref_l, ref_r)) {
    fprintf(stderr, "cannot read %s\n", argv[4]);
    return 1;
  }
  /* Load the library the way earshot.h tells hosts to: by ES_LIBRARY_SONAME,
   * here from the folder of the built file, so a header that names another
   * soname than the build makes fails this test. */
  char lib[4096];
  const char *slash = strrchr(argv[2], '/');
  int dir_len = slash ? (int)(slash - argv[2]) : 1;
  snprintf(lib, sizeof lib, "%.*s/%s", dir_len, slash ? argv[2] : ".", ES_LIBRARY_SONAME);
  const ESproctable *es = load(lib);
  if (!es || render_plugin(es)) return 1;

  double max_diff = 0.0, peak = 0.0, worst_ild = 0.0, worst_itd = 0.0;
  for (int i = 0; i < FRAMES; i++) {
    max_diff = fmax(max_diff, fmax(fabs(out_l[i] - ref_l[i]), fabs(out_r[i] - ref_r[i])));
    peak = fmax(peak, fmax(fabs(ref_l[i]), fabs(ref_r[i])));
  }
  for (int w = 0; w + WINDOW <= FRAMES; w += WINDOW) {
    const double d_ild = ild_db(out_l + w, out_r + w, WINDOW) - ild_db(ref_l + w, ref_r + w, WINDOW);
    const double d_itd = itd_s(out_l + w, out_r + w, WINDOW) - itd_s(ref_l + w, ref_r + w, WINDOW);
    worst_ild = fmax(worst_ild, fabs(d_ild));
    worst_itd = fmax(worst_itd, fabs(d_itd));
  }
  printf("plugin vs earshot render: ILD differs by at most %.4f dB, ITD by %.2f us (per 100 ms); "
         "largest sample difference %.2e (peak %.3f)\n",
         worst_ild, worst_itd * 1e6, max_diff, peak);
  if (peak < 0.01) {
    fprintf(stderr, "the reference is silent\n");
    return 1;
  }
  return worst_ild <= 0.1 && worst_itd <= 5e-6 && max_diff <= 1e-3 ? 0 : 1;
}
