# The LV2 plugin (lv2/): its DSP and tracker registry alone, the built
# binary under a small host of ours (allocation, worker, state), and real
# LV2 hosts (lv2_hosts.cmake).
earshot_unit_test(lv2_core_tests
  SOURCES lv2/test_binaural_panner.cpp audio/alloc_counter.cpp
  LIBS earshot_lv2_core earshot_analysis Threads::Threads
  THREAD_TESTS "SharedTrackers.*")
target_compile_definitions(lv2_core_tests PRIVATE EARSHOT_MAKE_SOFA="${PROJECT_SOURCE_DIR}/tests/fixtures/make_sofa.py")

earshot_unit_test(lv2_plugin_tests
  SOURCES lv2/test_lv2_plugin.cpp lv2/test_lv2_ambi_plugin.cpp audio/alloc_counter.cpp
  LIBS earshot_analysis PkgConfig::LV2 ${CMAKE_DL_LIBS}
  THREAD_TESTS "Lv2Plugin.TrackingFollowsTheSharedSimulatedHead:Lv2Plugin.RunNeverAllocates*:Lv2AmbiPlugin.RunNeverAllocates*")
target_compile_definitions(lv2_plugin_tests PRIVATE EARSHOT_LV2_BUNDLE="${EARSHOT_LV2_BUNDLE}"
  EARSHOT_MAKE_SOFA="${PROJECT_SOURCE_DIR}/tests/fixtures/make_sofa.py")
add_dependencies(lv2_plugin_tests earshot_lv2_bundle)

# State saved and restored by lilv, the host library under jalv and lv2apply.
pkg_check_modules(LILV_TESTS REQUIRED IMPORTED_TARGET lilv-0)
earshot_unit_test(lv2_state_tests
  SOURCES lv2/test_lv2_lilv_state.cpp
  LIBS PkgConfig::LILV_TESTS PkgConfig::LV2)
target_compile_definitions(lv2_state_tests PRIVATE EARSHOT_LV2_BUNDLE="${EARSHOT_LV2_BUNDLE}"
  EARSHOT_MAKE_SOFA="${PROJECT_SOURCE_DIR}/tests/fixtures/make_sofa.py" EARSHOT_WORK="${CMAKE_CURRENT_BINARY_DIR}/lv2_state")
add_dependencies(lv2_state_tests earshot_lv2_bundle)

# Real LV2 hosts: lilv's lv2apply against `earshot render` (cue table), and
# jalv in real time on JACK's dummy driver (tests/unit/lv2/test_lv2_jalv.cpp).
# Not in sanitizer trees: the hosts are not instrumented, so they cannot
# load an instrumented plugin.
if(NOT EARSHOT_SANITIZE)
  earshot_unit_test(lv2_host_tests
    SOURCES lv2/test_lv2_hosts.cpp
    LIBS earshot_analysis PkgConfig::SNDFILE_TESTS)
  target_compile_definitions(lv2_host_tests PRIVATE EARSHOT_LV2_PATH="${EARSHOT_LV2_PATH}"
    EARSHOT_EXE="$<TARGET_FILE:earshot>" EARSHOT_WORK="${CMAKE_CURRENT_BINARY_DIR}/lv2_hosts")
  add_dependencies(lv2_host_tests earshot_lv2_bundle earshot)

  pkg_check_modules(JACK_TESTS REQUIRED IMPORTED_TARGET jack)
  add_executable(lv2_jalv_tests lv2/test_lv2_jalv.cpp)
  target_link_libraries(lv2_jalv_tests PRIVATE earshot_analysis PkgConfig::JACK_TESTS PkgConfig::SNDFILE_TESTS
    Threads::Threads GTest::gtest GTest::gtest_main earshot_warnings)
  target_compile_definitions(lv2_jalv_tests PRIVATE EARSHOT_LV2_PATH="${EARSHOT_LV2_PATH}"
    EARSHOT_WORK="${CMAKE_CURRENT_BINARY_DIR}/lv2_jalv")
  add_dependencies(lv2_jalv_tests earshot_lv2_bundle)
  # Alone on the machine (RUN_SERIAL): it counts xruns.
  add_test(NAME lv2_jalv_tests COMMAND lv2_jalv_tests)
  set_tests_properties(lv2_jalv_tests PROPERTIES LABELS "unit;audio;lv2" TIMEOUT 120 RUN_SERIAL TRUE)
endif()

# The turtle through the LV2 validator (lv2_validate runs sord_validate with
# every installed LV2 specification).
add_test(NAME lv2_validate
  COMMAND sh -c "cd '${EARSHOT_LV2_BUNDLE}' && lv2_validate manifest.ttl earshot.ttl presets.ttl ambi.ttl 2>&1 | tee /dev/stderr | grep -q 'Found 0 errors'")
set_tests_properties(lv2_validate PROPERTIES LABELS "unit;lv2")

# The libraries earshot.so links, all named in docs/LV2.md.
add_test(NAME lv2_linked_libraries
  COMMAND ${CMAKE_COMMAND} -DLIB=$<TARGET_FILE:earshot_lv2> -DDOC=${PROJECT_SOURCE_DIR}/docs/LV2.md
          -P ${CMAKE_CURRENT_SOURCE_DIR}/lv2/linked_libraries.cmake)
set_tests_properties(lv2_linked_libraries PROPERTIES LABELS "unit;lv2;docs")
