/* Load Earshot with dlopen, place two sources, render one second. */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include "earshot/earshot.h"

int main(int argc, char **argv) {
  void *lib = dlopen(argc > 1 ? argv[1] : "libearshot.so.1", RTLD_NOW | RTLD_LOCAL);
  ESgetproctablefn get = NULL;
  if (lib) *(void **)(&get) = dlsym(lib, "esGetProcTable");
  const ESproctable *es = get ? get(ES_ABI_VERSION_MAJOR) : NULL;
  if (!es || es->size < sizeof(ESproctable)) { fprintf(stderr, "no Earshot ABI 1\n"); return 1; }
  ESworldparams p; ESworld world; ESbuffer tone; ESsource src[2];
  es->WorldParamsDefault(&p);
  if (es->CreateWorld(&p, &world) != ES_OK) { fprintf(stderr, "no world\n"); return 1; }
  static float pcm[48000], left[128], right[128];
  for (int i = 0; i < 48000; i++) pcm[i] = 0.25f * (float)sin(6.2831853 * 440.0 * i / 48000.0);
  es->CreateBuffer(world, pcm, 48000, 48000, &tone);
  for (int k = 0; k < 2; k++) {
    es->CreateSource(world, &src[k]);
    es->Sourcei(world, src[k], ES_BUFFER, (ESint)tone);
    es->Source3f(world, src[k], ES_POSITION, k ? 2.0f : -2.0f, 0.0f, -1.0f); /* left, right */
    es->Sourcef(world, src[k], ES_PITCH, k ? 1.5f : 1.0f);
    es->SourcePlay(world, src[k]);
  }
  double energy = 0.0;
  for (int b = 0; b < 375; b++) { /* 375 blocks of 128 frames: one second */
    es->Render(world, left, right, 128);
    for (int i = 0; i < 128; i++) energy += left[i] * left[i] + right[i] * right[i];
  }
  printf("rendered 1 s, RMS %.4f\n", sqrt(energy / (2.0 * 48000.0)));
  es->DestroyWorld(world);
  return energy > 0.0 ? 0 : 1;
}
