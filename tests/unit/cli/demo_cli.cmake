# `earshot demo` on its defaults where nothing can play: it must say why,
# track the simulated head, and leave a binaural WAV and a Pose track CSV that
# `earshot render` accepts.
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${EARSHOT} demo --duration 3 --out ${WORK}/demo.wav
                WORKING_DIRECTORY ${WORK} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "demo failed (${rc}): ${out} ${err}")
endif()
if(NOT out MATCHES "rendering to .*demo.wav instead of playing" OR NOT out MATCHES "circles" OR NOT out MATCHES "tracked")
  message(FATAL_ERROR "demo did not say what it did: ${out}")
endif()
if(NOT EXISTS ${WORK}/demo.wav OR NOT EXISTS ${WORK}/demo.poses.csv)
  message(FATAL_ERROR "demo left no WAV or pose track: ${out}")
endif()
execute_process(COMMAND ${EARSHOT} render --scene circles --duration 1 --pose-track ${WORK}/demo.poses.csv
                        --out ${WORK}/again.wav RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the demo's pose track does not replay (${rc}): ${out} ${err}")
endif()
execute_process(COMMAND ${EARSHOT} demo --tracker wiimote --out ${WORK}/x.wav RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--tracker: 'wiimote' cannot run offline")
  message(FATAL_ERROR "an offline-impossible tracker not reported (${rc}): ${err}")
endif()
