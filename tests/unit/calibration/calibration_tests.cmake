# Self-calibration of the LED model (issue 18 part 5): the bundle adjustment
# on short simulated sessions (quick) and on the issue's 60 s target (slow).
earshot_unit_test(led_calibration_tests
  SOURCES calibration/calibration_sim.hpp calibration/test_led_calibration.cpp
  LIBS earshot::tracker_calibration earshot::tracker_sim)

# `earshot track calibrate` end to end, and its refusals (exit code 2).
add_test(NAME cli_track_calibrate
  COMMAND ${CMAKE_COMMAND} -DEARSHOT=$<TARGET_FILE:earshot> -DWORK=${CMAKE_CURRENT_BINARY_DIR}/calibrate
          -P ${CMAKE_CURRENT_SOURCE_DIR}/calibration/calibrate_cli.cmake)
set_tests_properties(cli_track_calibrate PROPERTIES LABELS "unit;cli")

# The issue's 60 s targets (focal known and estimated): ~1 s each in Release,
# ~20 s under the sanitizers, so label slow rather than unit.
add_executable(led_calibration_target_tests calibration/calibration_sim.hpp calibration/test_led_calibration_target.cpp)
target_link_libraries(led_calibration_target_tests PRIVATE earshot::tracker_calibration earshot::tracker_sim GTest::gtest GTest::gtest_main earshot_warnings)
gtest_discover_tests(led_calibration_target_tests PROPERTIES LABELS slow DISCOVERY_TIMEOUT 60)
