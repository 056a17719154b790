# `earshot render`: the same scene twice gives the same bytes; a scene with an
# unknown field or a bad value gets one clear error naming file and field.
file(MAKE_DIRECTORY ${WORK})
file(WRITE ${WORK}/scene.json [=[
{"duration_s": 1, "sample_rate": 48000, "room": "none",
 "listener": {"position": [0, 0, 0], "yaw_deg": 30},
 "sources": [{"name": "noise", "signal": {"type": "noise", "seed": 7}, "position": [-1, 0, 0], "gain_db": -12},
             {"name": "tone", "signal": {"type": "sine", "frequency_hz": 500}, "position": [0, 1, -2],
              "distance_model": "linear-clamped", "max_distance": 10}]}
]=])
foreach(i 1 2)
  execute_process(COMMAND ${EARSHOT} render --scene ${WORK}/scene.json --out ${WORK}/out${i}.wav
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "48000 frames")
    message(FATAL_ERROR "render failed (${rc}): ${out} ${err}")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK}/out1.wav ${WORK}/out2.wav RESULT_VARIABLE same)
if(NOT same EQUAL 0)
  message(FATAL_ERROR "two renders of one scene differ")
endif()
file(WRITE ${WORK}/bad.json [=[{"sources": [{"signal": {"type": "noise"}, "gain_db": "loud"}]}]=])
execute_process(COMMAND ${EARSHOT} render --scene ${WORK}/bad.json --out ${WORK}/bad.wav RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "bad.json: field 'sources\\[0\\].gain_db': expected a number")
  message(FATAL_ERROR "bad scene not reported clearly (${rc}): ${err}")
endif()
file(WRITE ${WORK}/bad2.json [=[{"sources": [{"signal": {"type": "noise"}}], "colour": "blue"}]=])
execute_process(COMMAND ${EARSHOT} render --scene ${WORK}/bad2.json --out ${WORK}/bad.wav RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "field 'colour': unknown field")
  message(FATAL_ERROR "unknown field not reported (${rc}): ${err}")
endif()
execute_process(COMMAND ${EARSHOT} render --scene ${WORK}/scene.json --out ${WORK}/x.wav --hrtf ${WORK}/scene.json
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "scene.json: not a SOFA file")
  message(FATAL_ERROR "bad HRTF not reported (${rc}): ${err}")
endif()
