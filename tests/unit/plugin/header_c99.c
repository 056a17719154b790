/* earshot.h compiles as C99 with every warning an error (see CMakeLists). */
#include "earshot/earshot.h"
#include "earshot/earshot_openal_bridge.h"

int earshot_header_c99_compiles(void);
int earshot_header_c99_compiles(void) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  return (int)sizeof(ESproctable) + (int)p.size;
}
