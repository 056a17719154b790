# `earshot track calibrate` end to end: a simulated seated session from a
# starting model a few mm off gives a model `track solve` reads; recordings
# that cannot determine the model and bad options are refused with exit code 2.
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${EARSHOT} track simulate --motion seated --frames 2000 --seed 21 --out ${WORK}/session.csv
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "simulate failed: ${rc}")
endif()
# The thesis beacon with every LED moved 2-3 mm (LEDs 0 and 1 are 127.04 mm apart on the rig).
file(WRITE ${WORK}/start.json
  "{\"leds_mm\": [[65.5, 12.0, 4.5], [-61.5, 18.0, 1.0], [62.0, -67.5, 4.0], [-66.0, -14.5, 22.5]], \"half_angle_deg\": 45}")
execute_process(COMMAND ${EARSHOT} track calibrate --dots ${WORK}/session.csv --model ${WORK}/start.json
                        --out ${WORK}/model.json --scale-mm 127.04:0-1
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "RMS residual" OR NOT out MATCHES "least determined" OR NOT err MATCHES "calibrate: round 2")
  message(FATAL_ERROR "calibrate failed (${rc}): ${out} ${err}")
endif()
execute_process(COMMAND ${EARSHOT} track solve --dots ${WORK}/session.csv --model ${WORK}/model.json
                RESULT_VARIABLE rc OUTPUT_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "rotation error")
  message(FATAL_ERROR "solve with the calibrated model failed (${rc}): ${out}")
endif()
# A still head: 1000 identical frames of the beacon 1 m ahead.
set(still "t_s,x1,y1,x2,y2,x3,y3,x4,y4\n")
foreach(i RANGE 999)
  string(APPEND still "${i}e-2,593,401,431,405,594,300,431,363\n")
endforeach()
file(WRITE ${WORK}/still.csv "${still}")
execute_process(COMMAND ${EARSHOT} track calibrate --dots ${WORK}/still.csv --model ${WORK}/start.json
                        --out ${WORK}/x.json --scale-mm 127:0-1 RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "still.csv: too little motion to calibrate")
  message(FATAL_ERROR "a still head not refused clearly (${rc}): ${err}")
endif()
# Too few four-dot frames: the fourth dot is missing from all but 50 frames.
set(few "t_s,x1,y1,x2,y2,x3,y3,x4,y4\n")
foreach(i RANGE 999)
  if(i LESS 50)
    string(APPEND few "${i}e-2,593,401,431,405,594,300,431,363\n")
  else()
    string(APPEND few "${i}e-2,593,401,431,405,594,300,,\n")
  endif()
endforeach()
file(WRITE ${WORK}/few.csv "${few}")
execute_process(COMMAND ${EARSHOT} track calibrate --dots ${WORK}/few.csv --model ${WORK}/start.json
                        --out ${WORK}/x.json --scale-mm 127:0-1 RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "few.csv: too few frames with all four LEDs labelled to calibrate: [0-9]+ of 1000")
  message(FATAL_ERROR "too few four-dot frames not refused clearly (${rc}): ${err}")
endif()
# A scale pair that is not two distinct LEDs, and a ruler reading in cm.
execute_process(COMMAND ${EARSHOT} track calibrate --dots ${WORK}/session.csv --model ${WORK}/start.json
                        --out ${WORK}/x.json --scale-mm 127:1-1 RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--scale-mm: '127:1-1': the two LEDs must differ")
  message(FATAL_ERROR "a scale pair of one LED not refused clearly (${rc}): ${err}")
endif()
execute_process(COMMAND ${EARSHOT} track calibrate --dots ${WORK}/session.csv --model ${WORK}/start.json
                        --out ${WORK}/x.json --scale-mm 12.7:0-1 RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "--scale-mm: 12.7 mm between LEDs 0 and 1, but the starting model has them")
  message(FATAL_ERROR "a ruler reading far from the model not refused clearly (${rc}): ${err}")
endif()
if(EXISTS ${WORK}/x.json)
  message(FATAL_ERROR "a refused calibration wrote a model")
endif()
