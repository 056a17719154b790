# The webcam source (issue 19): spec, Y4M files, calibration and
# undistortion (against OpenCV), V4L2 errors, the source itself with a
# scripted detector.
find_package(OpenCV REQUIRED COMPONENTS core calib3d)
earshot_unit_test(webcam_source_tests
  SOURCES
    webcam_source/test_camera_calibration.cpp
    webcam_source/test_v4l2_camera.cpp
    webcam_source/test_webcam_source.cpp
    webcam_source/test_webcam_spec.cpp
    webcam_source/test_y4m_reader.cpp
  LIBS earshot::tracker_live opencv_core opencv_calib3d Threads::Threads
  THREAD_TESTS "WebcamSource.LiveTracker*")

# The whole chain from a rendered video (webcam/sim) to poses. LEDs and the
# LiveTracker thread are quick (~4 s each); the tag's video is slower to
# render and detect (~11 s), so it runs with the slow tests.
add_executable(webcam_source_e2e_tests webcam_source/test_webcam_end_to_end.cpp)
target_link_libraries(webcam_source_e2e_tests PRIVATE earshot::tracker_live earshot::webcam_sim GTest::gtest GTest::gtest_main
  earshot_warnings)
add_test(NAME webcam_source_e2e_leds COMMAND webcam_source_e2e_tests --gtest_filter=WebcamEndToEnd.Leds*)
add_test(NAME webcam_source_e2e_thread COMMAND webcam_source_e2e_tests --gtest_filter=WebcamEndToEnd.LiveTracker*)
set_tests_properties(webcam_source_e2e_leds webcam_source_e2e_thread PROPERTIES LABELS unit TIMEOUT 120)
add_test(NAME webcam_source_e2e_apriltag COMMAND webcam_source_e2e_tests --gtest_filter=WebcamEndToEnd.AprilTag*)
set_tests_properties(webcam_source_e2e_apriltag PROPERTIES LABELS slow TIMEOUT 300)
