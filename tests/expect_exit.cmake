# Runs COMMAND with ARGS (a ;-list) and checks its exit code and that its
# output (stdout and stderr) contains EXPECTED_OUTPUT, on one line.
execute_process(COMMAND ${COMMAND} ${ARGS} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL EXPECTED_EXIT)
  message(FATAL_ERROR "exit code ${code}, expected ${EXPECTED_EXIT}\nstdout: ${out}\nstderr: ${err}")
endif()
string(FIND "${out}${err}" "${EXPECTED_OUTPUT}" found)
if(found EQUAL -1)
  message(FATAL_ERROR "output lacks '${EXPECTED_OUTPUT}'\nstdout: ${out}\nstderr: ${err}")
endif()
message(STATUS "exit ${code} as expected: ${err}")
