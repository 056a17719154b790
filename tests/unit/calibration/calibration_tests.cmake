# Self-calibration of the LED model (issue 18 part 5): the bundle adjustment
# on short simulated sessions (quick) and on the issue's 60 s target (slow).
earshot_unit_test(led_calibration_tests
  SOURCES calibration/calibration_sim.hpp calibration/test_led_calibration.cpp
  LIBS earshot::tracker)
