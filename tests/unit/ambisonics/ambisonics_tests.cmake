# Ambisonics (issue 30): spherical harmonics and conventions, rotation.
earshot_unit_test(ambisonics_tests
  SOURCES
    ambisonics/test_rotation.cpp
    ambisonics/test_spherical_harmonics.cpp
    audio/alloc_counter.cpp
  LIBS earshot::ambisonics)
