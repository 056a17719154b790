# The near field (issue 15, part 5): the rigid-sphere model, the near-field
# filters and parallax, and renders against the model (KEMAR) and against a
# set measured at three distances (tests/fixtures/make_sofa.py).
earshot_unit_test(near_field_tests
  SOURCES near_field/test_rigid_sphere.cpp near_field/test_near_field.cpp near_field/test_near_field_render.cpp
    audio/alloc_counter.cpp
  LIBS earshot::audio earshot_analysis)
target_include_directories(near_field_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/audio)
target_compile_definitions(near_field_tests PRIVATE EARSHOT_MAKE_SOFA="${PROJECT_SOURCE_DIR}/tests/fixtures/make_sofa.py")
