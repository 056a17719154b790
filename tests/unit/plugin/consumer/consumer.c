/* Links libearshot (no dlopen): creates a world, renders a block. */
#include <stdio.h>
#include "earshot/earshot.h"

int main(void) {
  ESworldparams p;
  ESworld world = 0;
  float l[128], r[128];
  esWorldParamsDefault(&p);
  if (esCreateWorld(&p, &world) != ES_OK) return 1;
  ESenum e = esRender(world, l, r, 128);
  printf("consumer: %s\n", esGetErrorString(e));
  esDestroyWorld(world);
  return e == ES_OK ? 0 : 1;
}
