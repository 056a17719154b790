# The LV2 plugin (lv2/): its DSP and tracker registry alone, the built
# binary under a small host of ours (allocation, worker, state), and real
# LV2 hosts (lv2_hosts.cmake).
earshot_unit_test(lv2_core_tests
  SOURCES lv2/test_binaural_panner.cpp audio/alloc_counter.cpp
  LIBS earshot_lv2_core earshot_analysis Threads::Threads)

earshot_unit_test(lv2_plugin_tests
  SOURCES lv2/test_lv2_plugin.cpp audio/alloc_counter.cpp
  LIBS earshot_analysis PkgConfig::LV2 ${CMAKE_DL_LIBS})
target_compile_definitions(lv2_plugin_tests PRIVATE EARSHOT_LV2_BUNDLE="${EARSHOT_LV2_BUNDLE}"
  EARSHOT_MAKE_SOFA="${PROJECT_SOURCE_DIR}/tests/fixtures/make_sofa.py")
add_dependencies(lv2_plugin_tests earshot_lv2_bundle)

# Real LV2 hosts: lilv's lv2apply against `earshot render` (cue table), and
# the turtle through the LV2 validator (lv2_validate runs sord_validate with
# every installed LV2 specification).
earshot_unit_test(lv2_host_tests
  SOURCES lv2/test_lv2_hosts.cpp
  LIBS earshot_analysis PkgConfig::SNDFILE_TESTS)
target_compile_definitions(lv2_host_tests PRIVATE EARSHOT_LV2_PATH="${EARSHOT_LV2_PATH}"
  EARSHOT_EXE="$<TARGET_FILE:earshot>" EARSHOT_WORK="${CMAKE_CURRENT_BINARY_DIR}/lv2_hosts")
add_dependencies(lv2_host_tests earshot_lv2_bundle earshot)

add_test(NAME lv2_validate
  COMMAND sh -c "cd '${EARSHOT_LV2_BUNDLE}' && lv2_validate manifest.ttl earshot.ttl 2>&1 | tee /dev/stderr | grep -q 'Found 0 errors'")
set_tests_properties(lv2_validate PROPERTIES LABELS "unit;lv2")
