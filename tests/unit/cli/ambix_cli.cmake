# `earshot render --ambix`: an ambiX file rendered at its own rate (or
# --rate), a plane wave from the left heard on the left (and ahead with the
# head turned to it by a Pose track), both decoders, and a file whose channel
# count is not (N+1)^2 refused with an error naming it.
file(MAKE_DIRECTORY ${WORK})
set(py /usr/bin/python3 ${HELPER})
execute_process(COMMAND ${py} write ${WORK}/left.wav 4 44100 1.0 90 RESULT_VARIABLE rc)
execute_process(COMMAND ${py} write ${WORK}/five.wav 5 44100 0.2 0)
execute_process(COMMAND ${EARSHOT} render --ambix ${WORK}/left.wav --out ${WORK}/left_out.wav
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "44100 frames, 0 sources, 1 beds")
  message(FATAL_ERROR "render --ambix failed (${rc}): ${out} ${err}")
endif()
execute_process(COMMAND ${py} ild ${WORK}/left_out.wav OUTPUT_VARIABLE ild OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT ild GREATER 6)
  message(FATAL_ERROR "a wave from the left rendered with ILD ${ild} dB (expected > 6)")
endif()
# The head turned 90 degrees left (yaw about +y): the wave is ahead.
file(WRITE ${WORK}/turned.csv "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0,0.7071068,0,0.7071068,0\n10,0,0,0,0.7071068,0,0.7071068,0\n")
execute_process(COMMAND ${EARSHOT} render --ambix ${WORK}/left.wav --pose-track ${WORK}/turned.csv --decoder ls
                        --rate 48000 --out ${WORK}/turned_out.wav
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "48000 frames")
  message(FATAL_ERROR "render --ambix --rate 48000 --decoder ls failed (${rc}): ${out} ${err}")
endif()
execute_process(COMMAND ${py} ild ${WORK}/turned_out.wav OUTPUT_VARIABLE ild OUTPUT_STRIP_TRAILING_WHITESPACE)
if(ild GREATER 1 OR ild LESS -1)
  message(FATAL_ERROR "the head turned to the wave: ILD ${ild} dB (expected within 1 dB of 0)")
endif()
execute_process(COMMAND ${EARSHOT} render --ambix ${WORK}/five.wav --out ${WORK}/five_out.wav
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "five.wav: field 'channels': 5 channels is not an Ambisonic signal")
  message(FATAL_ERROR "a 5-channel file not refused clearly (${rc}): ${err}")
endif()
execute_process(COMMAND ${EARSHOT} render --ambix ${WORK}/left.wav --scene circles --out ${WORK}/x.wav
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(rc EQUAL 0)
  message(FATAL_ERROR "--ambix and --scene together were accepted")
endif()
# The tier on a scene: renders, and refuses a quality it does not know.
execute_process(COMMAND ${EARSHOT} render --scene manual --duration 0.5 --quality ambisonic:3 --out ${WORK}/tier.wav
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "24000 frames")
  message(FATAL_ERROR "render --quality ambisonic:3 failed (${rc}): ${out} ${err}")
endif()
execute_process(COMMAND ${EARSHOT} render --scene manual --duration 0.5 --quality ambisonic:9 --out ${WORK}/tier.wav
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--quality.*unknown quality 'ambisonic:9'")
  message(FATAL_ERROR "a bad --quality not refused clearly (${rc}): ${err}")
endif()
