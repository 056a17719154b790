# The docs name only what exists (tools/check_docs.py): the project's own docs
# pass, and a doc with one of each mistake gets each one reported.
# -DPYTHON -DTOOL -DROOT -DBUILD -DEARSHOT
execute_process(COMMAND ${PYTHON} ${TOOL} --root ${ROOT} --build ${BUILD} --earshot ${EARSHOT}
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the docs name what does not exist (exit ${rc}):\n${out}${err}")
endif()
message(STATUS "${out}")

execute_process(COMMAND ${PYTHON} ${TOOL} --root ${ROOT} --build ${BUILD} --earshot ${EARSHOT}
                        ${ROOT}/tests/unit/docs/broken_doc.md
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "the broken doc should exit 1, got ${rc}:\n${out}${err}")
endif()
foreach(expect
    "broken_doc.md:3: `earshot render` has no option --bogus"
    "broken_doc.md:6: `earshot track simulate` has no option --nonsense"
    "broken_doc.md:8: unknown command: earshot trak live"
    "broken_doc.md:9: `tools/plot_poses.py` has no option --nope"
    "broken_doc.md:10: no such path: ./scripts/run-nothing.sh"
    "broken_doc.md:13: no such path: audio/src/no_such_file.cpp"
    "broken_doc.md:13: no such header: earshot/no_such_header.hpp"
    "broken_doc.md:13: no such document in the repository: MISSING.md"
    "broken_doc.md:14: broken link: no/such/file.md")
  string(FIND "${out}" "${expect}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "not reported: ${expect}\ngot:\n${out}")
  endif()
endforeach()
