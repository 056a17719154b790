// earshot.h compiles as C++ with every warning an error (see CMakeLists).
#include "earshot/earshot.h"
#include "earshot/earshot_openal_bridge.h"

#include <type_traits>

static_assert(std::is_standard_layout_v<ESproctable>);
static_assert(std::is_standard_layout_v<ESworldparams>);
int earshot_header_cxx_compiles() { return static_cast<int>(sizeof(ESproctable)); }
