# tools/plot_poses.py writes a PNG from a simulated run and rejects bad input clearly.
file(MAKE_DIRECTORY ${WORK})
execute_process(COMMAND ${EARSHOT} track simulate --frames 300 --out ${WORK}/dots.csv RESULT_VARIABLE rc)
execute_process(COMMAND ${EARSHOT} track solve --dots ${WORK}/dots.csv --out ${WORK}/poses.csv RESULT_VARIABLE rc2 OUTPUT_QUIET)
if(NOT rc EQUAL 0 OR NOT rc2 EQUAL 0)
  message(FATAL_ERROR "simulate/solve failed")
endif()
file(REMOVE ${WORK}/out.png)
execute_process(COMMAND /usr/bin/python3 ${TOOL} --dots ${WORK}/dots.csv --poses ${WORK}/poses.csv --out ${WORK}/out.png
                RESULT_VARIABLE rc ERROR_VARIABLE err)
file(SIZE ${WORK}/out.png size)
if(NOT rc EQUAL 0 OR size LESS 20000)
  message(FATAL_ERROR "plot failed (${rc}, ${size} bytes): ${err}")
endif()
# The poses file has no ground truth columns: a clear error naming the file and column.
execute_process(COMMAND /usr/bin/python3 ${TOOL} --dots ${WORK}/poses.csv --poses ${WORK}/poses.csv --out ${WORK}/bad.png
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 2 OR NOT err MATCHES "poses.csv: missing column 'gt_tx_mm'")
  message(FATAL_ERROR "bad input not reported clearly (${rc}): ${err}")
endif()
