# SIGINT, SIGTERM and SIGHUP (Ctrl-C; `kill`, `timeout` and systemd; a closed
# terminal) end a recording or a render the same clean way:
#  - `track live --record`: exit 0, every row of the Pose track complete (eight
#    numbers and the state, the file ends with a newline), as many rows as the
#    tool says it recorded, and `render --pose-track` (the project's reader)
#    accepts it;
#  - `track record`: exit 0 and a Dots CSV that replays;
#  - `render`: exit 1 saying so, and a WAV whose header is final (RIFF and data
#    sizes match the file) holding as many frames as the tool says.
# signal_when_growing.sh sends the signal once the file has grown (mid-run on
# a slow machine too) and returns the tool's status; `track record` is stopped
# by `timeout`, as a script would.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})
file(WRITE ${WORK}/short.json "{\"duration_s\": 0.1, \"sample_rate\": 48000, \"room\": \"none\", \"listener\": {\"position\": [0, 0, 0]}, \"sources\": [{\"name\": \"tone\", \"signal\": {\"type\": \"sine\", \"frequency_hz\": 500}, \"position\": [0, 0, -2]}]}")
set(number "-?[0-9][0-9.e+-]*")

foreach(sig INT TERM HUP)
  set(csv ${WORK}/poses_${sig}.csv)
  execute_process(COMMAND ${CMAKE_CURRENT_LIST_DIR}/signal_when_growing.sh ${sig} ${csv} 3000
                          ${EARSHOT} track live --source sim --record ${csv}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  if(NOT rc EQUAL 0 OR NOT err MATCHES "stopped by SIG${sig}" OR NOT err MATCHES "recorded ([0-9]+) frames to")
    message(FATAL_ERROR "track live --record on SIG${sig}: status ${rc} (0 wanted): ${err}")
  endif()
  string(REGEX MATCH "recorded ([0-9]+) frames" said "${err}")
  set(said ${CMAKE_MATCH_1})
  file(READ ${csv} text)
  if(NOT text MATCHES "\n$")
    message(FATAL_ERROR "${csv} (SIG${sig}): the last row is torn (no newline at the end)")
  endif()
  file(STRINGS ${csv} lines)
  list(POP_FRONT lines header)
  list(LENGTH lines rows)
  if(NOT header STREQUAL "t_s,x_m,y_m,z_m,qw,qx,qy,qz,state" OR NOT rows EQUAL said OR rows LESS 10)
    message(FATAL_ERROR "${csv} (SIG${sig}): header '${header}', ${rows} rows; the tool said ${said}")
  endif()
  foreach(row IN LISTS lines)
    if(NOT row MATCHES "^${number},${number},${number},${number},${number},${number},${number},${number},(searching|tracking|predicted|lost)$")
      message(FATAL_ERROR "${csv} (SIG${sig}): incomplete row '${row}'")
    endif()
  endforeach()
  execute_process(COMMAND ${EARSHOT} render --scene ${WORK}/short.json --pose-track ${csv} --out ${WORK}/check.wav
                  RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 120)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the reader refused ${csv} (SIG${sig}): ${err}")
  endif()
endforeach()

execute_process(COMMAND timeout --preserve-status -s TERM 2 ${EARSHOT} track record --source sim --out ${WORK}/dots.csv
                RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0 OR NOT err MATCHES "stopped by SIGTERM.*recorded [0-9]+ frames")
  message(FATAL_ERROR "track record on SIGTERM: status ${rc} (0 wanted): ${err}")
endif()
execute_process(COMMAND ${EARSHOT} track live --source replay:${WORK}/dots.csv --fast
                RESULT_VARIABLE rc ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the dots recorded until SIGTERM do not replay (${rc}): ${err}")
endif()

# Ten minutes of the traffic preset: far more than a few seconds render.
foreach(sig INT TERM HUP)
  set(wav ${WORK}/render_${sig}.wav)
  execute_process(COMMAND ${CMAKE_CURRENT_LIST_DIR}/signal_when_growing.sh ${sig} ${wav} 100000
                          ${EARSHOT} render --scene traffic --duration 600 --format pcm24 --out ${wav}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
  if(NOT rc EQUAL 1 OR NOT err MATCHES "stopped by SIG${sig}: .* is a valid WAV of the first ([0-9]+) frames")
    message(FATAL_ERROR "render on SIG${sig}: status ${rc} (1 wanted): ${out} ${err}")
  endif()
  set(said ${CMAKE_MATCH_1})
  execute_process(COMMAND /usr/bin/python3 ${CMAKE_CURRENT_LIST_DIR}/wav_check.py ${wav}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE frames ERROR_VARIABLE err OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT rc EQUAL 0 OR NOT frames EQUAL said OR said EQUAL 0)
    message(FATAL_ERROR "${wav} (SIG${sig}): ${err} ${frames} frames in the file; the tool said ${said}")
  endif()
endforeach()
