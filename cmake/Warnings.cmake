# Project-wide warning set, applied per target through earshot_warnings().
add_library(earshot_warnings INTERFACE)
target_compile_options(earshot_warnings INTERFACE
  $<$<COMPILE_LANG_AND_ID:CXX,GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion>
  $<$<COMPILE_LANG_AND_ID:C,GNU,Clang>:-Wall -Wextra -Wpedantic>)
# CI builds Release with -Werror (scripts/run-tests.sh): the tree stays warning-free.
option(EARSHOT_WERROR "Treat compiler warnings as errors" OFF)
if(EARSHOT_WERROR)
  target_compile_options(earshot_warnings INTERFACE -Werror)
endif()
