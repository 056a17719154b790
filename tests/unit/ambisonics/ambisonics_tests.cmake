# Ambisonics (issue 30): spherical harmonics and conventions, rotation, the
# binaural decoder's design and convolver, ambiX files; the decoder cache and
# the Ambisonic tier's bus inside the renderer.
earshot_unit_test(ambisonics_tests
  SOURCES
    ambisonics/test_ambisonic_bus.cpp
    ambisonics/test_ambix_file.cpp
    ambisonics/test_binaural_decoder.cpp
    ambisonics/test_decoder_cache.cpp
    ambisonics/test_rotation.cpp
    ambisonics/test_spherical_harmonics.cpp
    audio/alloc_counter.cpp
  LIBS earshot::ambisonics PkgConfig::SNDFILE_TESTS)
