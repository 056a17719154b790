# Ambisonics (issue 30): spherical harmonics and conventions, rotation, the
# binaural decoder's design and convolver.
earshot_unit_test(ambisonics_tests
  SOURCES
    ambisonics/test_binaural_decoder.cpp
    ambisonics/test_rotation.cpp
    ambisonics/test_spherical_harmonics.cpp
    audio/alloc_counter.cpp
  LIBS earshot::ambisonics)
