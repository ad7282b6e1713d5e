# Fails if any C or OpenCL source differs from what .clang-format asks for.
file(GLOB_RECURSE sources ${SOURCE_DIR}/host/*.c ${SOURCE_DIR}/host/*.h ${SOURCE_DIR}/kernels/*.h
     ${SOURCE_DIR}/kernels/*.cl ${SOURCE_DIR}/tests/*.c ${SOURCE_DIR}/tests/*.h ${SOURCE_DIR}/bench/*.c)
set(unformatted "")
foreach(source ${sources})
  execute_process(COMMAND ${CLANG_FORMAT} --dry-run -Werror ${source} RESULT_VARIABLE code OUTPUT_QUIET ERROR_QUIET)
  if(NOT code EQUAL 0)
    list(APPEND unformatted ${source})
  endif()
endforeach()
if(unformatted)
  string(REPLACE ";" "\n  " list "${unformatted}")
  message(FATAL_ERROR "not formatted as .clang-format says (run clang-format -i):\n  ${list}")
endif()
