# The near field (issue 15, part 5): the rigid-sphere model, the near-field
# filters and parallax, and renders against the model and a multi-distance set.
earshot_unit_test(near_field_tests
  SOURCES near_field/test_rigid_sphere.cpp
  LIBS earshot::hrtf)
