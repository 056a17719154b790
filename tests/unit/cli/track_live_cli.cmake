# End-to-end check of `earshot track live` / `track record`: a simulated run
# recorded as a Pose track CSV that `render --pose-track` accepts, recorded
# dots replayed, and clear failures (no Wii Remote, a bad source) that exit
# instead of hanging.
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${EARSHOT} track record --source sim --fast --duration 0.5 --out ${WORK}/dots.csv
                RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0 OR NOT err MATCHES "recorded [0-9]+ frames")
  message(FATAL_ERROR "track record failed (${rc}): ${err}")
endif()
execute_process(COMMAND ${EARSHOT} track live --source replay:${WORK}/dots.csv --fast --record ${WORK}/poses.csv
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
if(NOT rc EQUAL 0 OR NOT err MATCHES "poses published")
  message(FATAL_ERROR "track live on the replay failed (${rc}): ${err}")
endif()
file(STRINGS ${WORK}/poses.csv lines)
list(GET lines 0 header)
list(LENGTH lines n)
if(NOT header STREQUAL "t_s,x_m,y_m,z_m,qw,qx,qy,qz,state" OR n LESS 10)
  message(FATAL_ERROR "poses.csv: header '${header}', ${n} lines")
endif()
file(WRITE ${WORK}/scene.json "{\"duration_s\": 0.2, \"sample_rate\": 48000, \"room\": \"none\", \"listener\": {\"position\": [0, 0, 0]}, \"sources\": [{\"name\": \"tone\", \"signal\": {\"type\": \"sine\", \"frequency_hz\": 500}, \"position\": [0, 0, -2]}]}")
execute_process(COMMAND ${EARSHOT} render --scene ${WORK}/scene.json --pose-track ${WORK}/poses.csv --out ${WORK}/out.wav
                RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 120)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "render refused the recorded pose track (${rc}): ${err}")
endif()
# No remote on a test machine: a clear message and exit code 1, well within the duration.
execute_process(COMMAND ${EARSHOT} track live --source wiimote --duration 20
                RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 30)
if(NOT rc EQUAL 1 OR NOT err MATCHES "no Wii Remote found.*bluetoothctl")
  message(FATAL_ERROR "--source wiimote without a remote (${rc}): ${err}")
endif()
execute_process(COMMAND ${EARSHOT} track live --source bogus RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 30)
if(NOT rc EQUAL 2 OR NOT err MATCHES "unknown source 'bogus'")
  message(FATAL_ERROR "bad source not reported clearly (${rc}): ${err}")
endif()
execute_process(COMMAND ${EARSHOT} track record --source osc --out ${WORK}/x.csv RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 30)
if(NOT rc EQUAL 2 OR NOT err MATCHES "sends poses, not dots")
  message(FATAL_ERROR "record from a pose source not refused clearly (${rc}): ${err}")
endif()
# --send: where the poses go, said at the start and counted at the end; a bad
# spec is an input error naming --send and the spec; a host that does not
# resolve ends the run with a message, before tracking starts. (Nothing
# listens on these ports: UDP needs no one to take the datagrams.)
execute_process(COMMAND ${EARSHOT} track live --source replay:${WORK}/dots.csv --fast
                        --send osc:127.0.0.1:39871,format=sparta --send opentrack:39872,rate=50
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
if(NOT rc EQUAL 0 OR NOT err MATCHES "sending poses to osc 127.0.0.1:39871 \\(sparta, 100/s\\)"
   OR NOT err MATCHES "sending poses to opentrack 127.0.0.1:39872 \\(50/s\\)" OR NOT err MATCHES "sent [1-9][0-9]* poses to osc")
  message(FATAL_ERROR "track live --send (${rc}): ${err}")
endif()
execute_process(COMMAND ${EARSHOT} track live --source sim --send osc:70000 RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 30)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--send: send 'osc:70000': bad UDP port '70000'")
  message(FATAL_ERROR "bad --send not reported clearly (${rc}): ${err}")
endif()
execute_process(COMMAND ${EARSHOT} track live --source sim --send osc:no-such-host.invalid
                RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 30)
if(rc EQUAL 0 OR NOT err MATCHES "cannot resolve host 'no-such-host.invalid'")
  message(FATAL_ERROR "--send to a host that does not resolve (${rc}): ${err}")
endif()
