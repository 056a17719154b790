# The C host (dlopen) against `earshot render` on one scene: two noise
# sources from WAV files, the listener turned 20 degrees, a living room on
# the send bus. The host prints the cue differences; it fails when they
# exceed 0.1 dB ILD, 5 us ITD or 1e-3 in any sample.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${HOST} inputs ${WORK} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "writing the inputs failed")
endif()
file(WRITE ${WORK}/scene.json [=[
{"duration_s": 1, "sample_rate": 48000, "room": "living-room",
 "listener": {"position": [0, 0, 0], "yaw_deg": 20},
 "sources": [{"name": "a", "signal": {"type": "file", "path": "a.wav"}, "position": [-1, 0, -1],
              "reverb_send_db": -10},
             {"name": "b", "signal": {"type": "file", "path": "b.wav"}, "position": [2, 0, 0.5], "gain_db": -6}]}
]=])
execute_process(COMMAND ${EARSHOT} render --scene ${WORK}/scene.json --out ${WORK}/ref.wav
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "earshot render failed (${rc}): ${out} ${err}")
endif()
execute_process(COMMAND ${HOST} compare ${LIB} ${WORK} ${WORK}/ref.wav RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "${out}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "plugin and earshot render disagree (${rc}): ${out} ${err}")
endif()
