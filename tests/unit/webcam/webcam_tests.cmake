# Webcam detection (issue 19): the LED and AprilTag detectors on hand-drawn
# and libapriltag-rendered frames.
pkg_check_modules(WEBCAM_TEST_APRILTAG REQUIRED IMPORTED_TARGET apriltag)
earshot_unit_test(webcam_tests
  SOURCES webcam/frame_drawing.hpp webcam/test_led_detector.cpp webcam/test_apriltag_detector.cpp
  LIBS earshot::webcam PkgConfig::WEBCAM_TEST_APRILTAG)

# Synthetic webcam video (rendered head walks) against its projected truth,
# and the Y4M writer.
earshot_unit_test(webcam_sim_tests
  SOURCES webcam/test_video_sim.cpp
  LIBS earshot::webcam_sim)
