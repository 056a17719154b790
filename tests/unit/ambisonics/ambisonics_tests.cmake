# Ambisonics (issue 30): spherical harmonics and conventions, rotation, the
# binaural decoder's design and convolver, ambiX files.
earshot_unit_test(ambisonics_tests
  SOURCES
    ambisonics/test_ambix_file.cpp
    ambisonics/test_binaural_decoder.cpp
    ambisonics/test_rotation.cpp
    ambisonics/test_spherical_harmonics.cpp
    audio/alloc_counter.cpp
  LIBS earshot::ambisonics PkgConfig::SNDFILE_TESTS)
