# earshot-openal-run's command line, as a user meets it (LAUNCHER: the executable).
function(run expect_rc)
  execute_process(COMMAND ${LAUNCHER} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 30)
  if(NOT rc EQUAL expect_rc)
    message(FATAL_ERROR "earshot-openal-run ${ARGN}: exit ${rc}, expected ${expect_rc}: ${out} ${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
  set(err "${err}" PARENT_SCOPE)
endfunction()

run(0 --help)
if(NOT out MATCHES "earshot-openal-run .*mpg123 -o openal" OR NOT out MATCHES "--tracker")
  message(FATAL_ERROR "--help shows no example or no --tracker: ${out}")
endif()
run(127 -- earshot-no-such-program-here)
if(NOT err MATCHES "earshot-openal-run: earshot-no-such-program-here: command not found")
  message(FATAL_ERROR "a missing program is not named: ${err}")
endif()
run(2 --tracker nonsense:1 -- true)
if(NOT err MATCHES "^earshot-openal-run: .*nonsense")
  message(FATAL_ERROR "a bad tracker spec is not named: ${err}")
endif()
run(2)
# The program runs with the shim first in LD_PRELOAD (anything there before
# kept after it) and the options in the environment; its exit code is passed on.
set(ENV{LD_PRELOAD} "/earshot-test-before.so")  # ld.so says it cannot load it and goes on
run(0 --tracker sim --place none -- sh -c
    "echo \"$LD_PRELOAD\" | grep -q '/libearshot_openal_preload.so /earshot-test-before.so$' && test \"$EARSHOT_OPENAL_TRACKER\" = sim && test \"$EARSHOT_OPENAL_PLACE\" = none")
run(7 -- sh -c "exit 7")
message(STATUS "earshot-openal-run: help, missing program, bad spec, environment and exit codes as expected")
