# Configures a sub-build with clang and -DGMON_UBSAN=ON in BUILD_DIR, builds
# only TESTS (a list of test targets) and runs them there.
# Usage: cmake -DCLANG=... -DSOURCE_DIR=... -DBUILD_DIR=... -DTESTS=a;b -P clang_ubsan.cmake
if(NOT CLANG OR NOT EXISTS "${CLANG}")
  message(FATAL_ERROR "clang not found (scripts/install-deps.sh installs it)")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${BUILD_DIR} -DCMAKE_C_COMPILER=${CLANG}
          -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGMON_UBSAN=ON -DGMON_WERROR=ON -DGMON_CLANG_UBSAN_TEST=OFF
  RESULT_VARIABLE result)
if(result)
  message(FATAL_ERROR "configuring ${BUILD_DIR} failed")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${BUILD_DIR} -j 2 --target ${TESTS} RESULT_VARIABLE result)
if(result)
  message(FATAL_ERROR "building ${TESTS} with clang failed")
endif()
list(JOIN TESTS "|" pattern)
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --test-dir ${BUILD_DIR} -R "^(${pattern})$" --output-on-failure
                RESULT_VARIABLE result)
if(result)
  message(FATAL_ERROR "tests under clang's UBSan failed")
endif()
