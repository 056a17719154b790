# earshot-openal-run with real OpenAL programs from Debian (pyglet, gstreamer's
# openalsink, mpg123 -o openal), OpenAL Soft's wave backend capturing what
# they play (tests/unit/preload/openal_run_check.py; docs/OPENAL_RUN.md).
# Included from tests/unit/CMakeLists.txt.
set(preload_dir ${CMAKE_CURRENT_SOURCE_DIR}/preload)

# Our own OpenAL program on the loopback device (preload_probe.cpp): a
# thread-local context, read-back, contexts destroyed while poses arrive,
# the head's offset in the listener's frame, a device closed under a live
# context, --recenter-after. Without the shim it must fail where
# the head turn is not heard.
pkg_check_modules(OPENAL_PRELOAD_TESTS REQUIRED IMPORTED_TARGET openal)
add_executable(preload_probe preload/preload_probe.cpp)
target_link_libraries(preload_probe PRIVATE PkgConfig::OPENAL_PRELOAD_TESTS earshot_warnings)
add_test(NAME preload_probe COMMAND earshot-openal-run --tracker osc:19245 -- $<TARGET_FILE:preload_probe> 19245)
add_test(NAME preload_probe_without_shim COMMAND preload_probe 19246)
add_test(NAME preload_probe_recenter
  COMMAND earshot-openal-run --tracker osc:19247 --recenter-after 1 -- $<TARGET_FILE:preload_probe> 19247 recenter)
set_tests_properties(preload_probe_without_shim PROPERTIES
  PASS_REGULAR_EXPRESSION "ILD [-+0-9.]+ dB never passed -6.0+ dB: the listener did not follow the head")
set_tests_properties(preload_probe preload_probe_without_shim preload_probe_recenter
  PROPERTIES LABELS "unit;preload" TIMEOUT 60)

# The rest preloads the shim into uninstrumented programs (python3,
# gst-launch-1.0, mpg123), where a sanitized library cannot load: not under
# sanitizers (the probe above runs there: it is instrumented itself).
if(EARSHOT_SANITIZE)
  return()
endif()
set(preload_check /usr/bin/python3 ${preload_dir}/openal_run_check.py
    --launcher $<TARGET_FILE:earshot-openal-run> --pyglet-script ${preload_dir}/pyglet_sources.py)

# The launcher's command line: help with an example, 127 for a missing
# program, 2 for a bad tracker spec, the program's own exit code passed on;
# a tracker that cannot start is named and the program plays on.
add_test(NAME preload_launcher_cli
  COMMAND ${CMAKE_COMMAND} -DLAUNCHER=$<TARGET_FILE:earshot-openal-run> -DWORK=${CMAKE_CURRENT_BINARY_DIR}/preload_launcher_cli
          -P ${preload_dir}/launcher_cli.cmake)

# Quick: gstreamer's openalsink and mpg123 (stereo streams) and a pyglet
# program (a mono source ahead, which also reads its listener back), without
# the shim and with the head turned 60 degrees left.
add_test(NAME preload_gst_turn
  COMMAND ${preload_check} --program gst --conditions none,60 --port 19241 --work ${CMAKE_CURRENT_BINARY_DIR}/preload_gst_turn)
add_test(NAME preload_pyglet_turn
  COMMAND ${preload_check} --program pyglet --conditions none,60 --port 19242 --work ${CMAKE_CURRENT_BINARY_DIR}/preload_pyglet_turn)
add_test(NAME preload_mpg123_turn
  COMMAND ${preload_check} --program mpg123 --conditions none,60 --port 19243 --work ${CMAKE_CURRENT_BINARY_DIR}/preload_mpg123_turn)
set_tests_properties(preload_launcher_cli preload_gst_turn preload_pyglet_turn preload_mpg123_turn
  PROPERTIES LABELS "unit;preload" TIMEOUT 60)

# Every program at head yaw 0, +60 and -60 against its no-shim baseline
# (about 10 s each: four runs in real time).
add_test(NAME preload_pyglet_yaws
  COMMAND ${preload_check} --program pyglet --port 19251 --work ${CMAKE_CURRENT_BINARY_DIR}/preload_pyglet_yaws)
add_test(NAME preload_gst_yaws
  COMMAND ${preload_check} --program gst --port 19252 --work ${CMAKE_CURRENT_BINARY_DIR}/preload_gst_yaws)
add_test(NAME preload_mpg123_yaws
  COMMAND ${preload_check} --program mpg123 --port 19253 --work ${CMAKE_CURRENT_BINARY_DIR}/preload_mpg123_yaws)
# A mono stream that gstreamer plays at the listener follows the head only
# with --place all (moved 1 m ahead into the room).
add_test(NAME preload_gst_mono_yaws
  COMMAND ${preload_check} --program gst-mono --place all --port 19254 --work ${CMAKE_CURRENT_BINARY_DIR}/preload_gst_mono_yaws)
set_tests_properties(preload_pyglet_yaws preload_gst_yaws preload_mpg123_yaws preload_gst_mono_yaws
  PROPERTIES LABELS "slow;preload" TIMEOUT 180)
