# CTest fuzz_build: configures and builds the libFuzzer harnesses of
# tests/fuzz in their own clang build.
# cmake -DCLANG=<clang> -DSOURCE_DIR=<repo> -DFUZZ_DIR=<build/fuzz> -P build_fuzzers.cmake
if(NOT CLANG OR NOT EXISTS "${CLANG}")
  message(FATAL_ERROR "clang not found (scripts/install-deps.sh installs it)")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${FUZZ_DIR} -DCMAKE_C_COMPILER=${CLANG} -DGMON_FUZZ=ON
          -DGMON_WERROR=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
  RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "configuring the fuzz build in ${FUZZ_DIR} failed")
endif()
cmake_host_system_information(RESULT cores QUERY NUMBER_OF_LOGICAL_CORES)
execute_process(COMMAND ${CMAKE_COMMAND} --build ${FUZZ_DIR} -j ${cores} RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "building the fuzz harnesses failed (clang needs the libFuzzer runtime: libclang-rt-dev)")
endif()
