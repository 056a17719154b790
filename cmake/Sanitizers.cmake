# EARSHOT_SANITIZE=address,undefined or thread: applied to every target in the tree.
if(EARSHOT_SANITIZE)
  message(STATUS "earshot: sanitizers ${EARSHOT_SANITIZE}")
  add_compile_options(-fsanitize=${EARSHOT_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${EARSHOT_SANITIZE})
  # clang puts the sanitizer runtime into executables only, and for a C
  # executable leaves out its C++ half (UBSan's vptr checks). The C hosts
  # dlopen the C++ library, which needs that half: link it in (with the C++
  # runtime library it is written against).
  if(CMAKE_C_COMPILER_ID STREQUAL "Clang" AND EARSHOT_SANITIZE MATCHES "undefined")
    add_link_options($<$<LINK_LANGUAGE:C>:-fsanitize-link-c++-runtime> $<$<LINK_LANGUAGE:C>:-lstdc++>)
  endif()
endif()

# Fuzz builds instrument the sources that parse outside bytes for coverage
# too (not only the fuzz targets): libFuzzer is then guided by the parsers'
# own branches (fuzz_osc_pose: 751 coverage points where the harness alone
# saw 82). Only those sources: coverage hooks on every comparison would slow
# the DSP and solver code that the same tree's unit tests spend their time in.
# Call from the directory that builds the sources.
function(earshot_fuzz_coverage_sources)
  if(EARSHOT_BUILD_FUZZ)
    set_property(SOURCE ${ARGN} APPEND PROPERTY COMPILE_OPTIONS -fsanitize=fuzzer-no-link)
    set_property(SOURCE ${ARGN} PROPERTY SKIP_UNITY_BUILD_INCLUSION ON)  # a unity batch would drop the option
  endif()
endfunction()
