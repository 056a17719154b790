# The plugin (libearshot.so, its C API) and the OpenAL Soft bridge.
# Included from tests/unit/CMakeLists.txt.
set(plugin_dir ${CMAKE_CURRENT_SOURCE_DIR}/plugin)

# earshot.h (and the bridge's header) compile as C99 and as C++ with every
# warning an error.
add_library(plugin_header_check OBJECT plugin/header_c99.c plugin/header_cxx.cpp)
target_include_directories(plugin_header_check PRIVATE
  ${PROJECT_SOURCE_DIR}/plugin/include ${PROJECT_SOURCE_DIR}/plugin/bridge/include)
set_target_properties(plugin_header_check PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF)
target_compile_options(plugin_header_check PRIVATE
  $<$<COMPILE_LANGUAGE:C>:-Wall -Wextra -Wpedantic -Wconversion -Wshadow -Wstrict-prototypes -Werror>
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wconversion -Wshadow -Wold-style-cast -Werror>)

# The C host: compiled as C, loads the library with dlopen (not linked).
add_executable(plugin_host_test plugin/host_test.c)
target_include_directories(plugin_host_test PRIVATE ${PROJECT_SOURCE_DIR}/plugin/include)
set_target_properties(plugin_host_test PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF)
target_link_libraries(plugin_host_test PRIVATE PkgConfig::SNDFILE_TESTS ${CMAKE_DL_LIBS} m earshot_warnings)
add_dependencies(plugin_host_test earshot_plugin plugin_header_check)
add_test(NAME plugin_host_vs_render
  COMMAND ${CMAKE_COMMAND} -DHOST=$<TARGET_FILE:plugin_host_test> -DLIB=$<TARGET_FILE:earshot_plugin>
          -DEARSHOT=$<TARGET_FILE:earshot> -DWORK=${CMAKE_CURRENT_BINARY_DIR}/plugin_host
          -P ${plugin_dir}/host_vs_render.cmake)
set_tests_properties(plugin_host_vs_render PROPERTIES LABELS "unit;plugin")

# Only the API leaves the libraries.
add_test(NAME plugin_exports
  COMMAND ${CMAKE_COMMAND} -DLIB=$<TARGET_FILE:earshot_plugin> -DPREFIX=es -DMUST=esGetProcTable
          -P ${plugin_dir}/nm_exports.cmake)
add_test(NAME plugin_bridge_exports
  COMMAND ${CMAKE_COMMAND} -DLIB=$<TARGET_FILE:earshot_openal_bridge> -DPREFIX=esal -DMUST=esalBridgeUpdate
          -P ${plugin_dir}/nm_exports.cmake)
set_tests_properties(plugin_exports plugin_bridge_exports PROPERTIES LABELS "unit;plugin")

# The API linked: ABI, deferred mode, sources, misuse, control and audio
# threads together (CI runs these under TSan too), no allocation
# in esRender, head poses.
# test_tracker_state also compiles the library's status mapping
# (plugin/src/tracker_state.cpp) to map a scripted Wii Remote session;
# test_tracker_image renders a webcam video (earshot::webcam_sim) to play.
earshot_unit_test(plugin_tests
  SOURCES plugin/test_plugin.cpp plugin/test_tracker_state.cpp plugin/test_world_hrtf.cpp audio/alloc_counter.cpp
    plugin/test_tracker_image.cpp plugin/test_ambisonic_world.cpp
    ${PROJECT_SOURCE_DIR}/plugin/src/tracker_state.cpp
  LIBS earshot_plugin earshot::tracker_live earshot::webcam_sim earshot::ambisonics earshot_analysis ${CMAKE_DL_LIBS}
    Threads::Threads
  # Misuse from other threads, control and audio threads together, the live
  # tracker thread behind a world (single-threaded API tests run once).
  THREAD_TESTS "PluginMisuse.*:PluginThreads.*:PluginHead.*" "TrackerState.*:WorldHrtf.*Thread*:TrackerImage.*"
    "AmbisonicThreads.*")
target_include_directories(plugin_tests PRIVATE ${PROJECT_SOURCE_DIR}/plugin/src)
target_compile_definitions(plugin_tests PRIVATE EARSHOT_MAKE_SOFA="${PROJECT_SOURCE_DIR}/tests/fixtures/make_sofa.py")

# The OpenAL Soft bridge on the loopback device with HRTF.
pkg_check_modules(OPENAL_TESTS REQUIRED IMPORTED_TARGET openal)
earshot_unit_test(plugin_bridge_tests
  SOURCES plugin/test_bridge.cpp
  LIBS earshot_openal_bridge earshot_analysis PkgConfig::OPENAL_TESTS)
target_compile_definitions(plugin_bridge_tests PRIVATE EARSHOT_RECORDED_TURN="${plugin_dir}/recorded_turn.csv")

# The example of docs/PLUGIN.md, run.
add_test(NAME plugin_example_two_sources COMMAND plugin_example_two_sources $<TARGET_FILE:earshot_plugin>)
set_tests_properties(plugin_example_two_sources PROPERTIES LABELS "unit;plugin")

# Installed, the plugin is found by pkg-config and by find_package(earshot).
# Not in sanitizer builds: the consumer it compiles is a plain program, which
# cannot load an instrumented library.
if(NOT EARSHOT_SANITIZE)
  add_test(NAME plugin_install
    COMMAND ${CMAKE_COMMAND} -DBUILD=${PROJECT_BINARY_DIR} -DSRC=${plugin_dir} -DWORK=${CMAKE_CURRENT_BINARY_DIR}/plugin_install
            -P ${plugin_dir}/install_check.cmake)
  set_tests_properties(plugin_install PROPERTIES LABELS "unit;plugin")
endif()
