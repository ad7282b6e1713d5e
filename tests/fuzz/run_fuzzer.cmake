# CTest fuzz_<harness>: runs one libFuzzer harness of tests/fuzz for a
# bounded time on a fresh copy of its seeds (the project's scenes and data,
# ../shared/scenes, tests/fuzz/corpus). Fails on a crash, leak, UB report,
# timeout or out-of-memory; libFuzzer saves the input in FUZZ_DIR/findings/.
# cmake -DHARNESS=scene|ply|exr|image -DSOURCE_DIR=<repo> -DFUZZ_DIR=<build/fuzz> -DSECONDS=40 -P run_fuzzer.cmake
set(max_len 65536)
set(seeds ${FUZZ_DIR}/seeds/${HARNESS})
set(corpus ${FUZZ_DIR}/corpus/${HARNESS}) # what this run adds
set(temporary ${FUZZ_DIR}/tmp/${HARNESS})
set(log_file ${FUZZ_DIR}/fuzz_${HARNESS}.log)
file(REMOVE_RECURSE ${seeds} ${corpus} ${temporary})
file(MAKE_DIRECTORY ${seeds} ${corpus} ${temporary} ${FUZZ_DIR}/findings)

# Copies the files under `root` matching the globs, of at most max_len
# bytes, into the seeds, each named `prefix` and its path.
function(copy_seeds prefix root)
  foreach(glob ${ARGN})
    file(GLOB_RECURSE files RELATIVE ${root} ${root}/${glob})
    foreach(file ${files})
      file(SIZE ${root}/${file} size)
      if(size LESS_EQUAL max_len)
        string(REPLACE "/" "_" name "${prefix}_${file}")
        file(COPY_FILE ${root}/${file} ${seeds}/${name})
      endif()
    endforeach()
  endforeach()
endfunction()

set(shared_scenes ${SOURCE_DIR}/../shared/scenes)
if(NOT IS_DIRECTORY ${shared_scenes})
  message(STATUS "no ${shared_scenes}: seeds from the project only")
endif()
set(options)
if(HARNESS STREQUAL "scene")
  copy_seeds(own ${SOURCE_DIR}/tests/fuzz/corpus/scene "*")
  copy_seeds(project ${SOURCE_DIR} "scenes/*.pbrt" "tests/data/*.pbrt")
  copy_seeds(shared ${shared_scenes} "*.pbrt")
  list(APPEND options -dict=${SOURCE_DIR}/tests/fuzz/scene.dict)
elseif(HARNESS STREQUAL "ply")
  copy_seeds(own ${SOURCE_DIR}/tests/fuzz/corpus/ply "*")
  copy_seeds(project ${SOURCE_DIR} "tests/data/*.ply")
  copy_seeds(shared ${shared_scenes} "*.ply")
elseif(HARNESS STREQUAL "exr")
  copy_seeds(own ${SOURCE_DIR}/tests/fuzz/corpus/exr "*")
  copy_seeds(project ${SOURCE_DIR} "tests/data/*.exr")
  execute_process(COMMAND ${FUZZ_DIR}/make_exr_seeds ${seeds} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "make_exr_seeds failed")
  endif()
elseif(HARNESS STREQUAL "image")
  copy_seeds(own ${SOURCE_DIR}/tests/fuzz/corpus/image "*")
  copy_seeds(shared ${shared_scenes} "*.png" "*.jpg" "*.tga" "*.bmp" "*.hdr" "*.pfm")
else()
  message(FATAL_ERROR "unknown harness '${HARNESS}'")
endif()
file(GLOB seed_files ${seeds}/*)
list(LENGTH seed_files seed_count)
message(STATUS "fuzz_${HARNESS}: ${seed_count} seeds, ${SECONDS} s")

set(ENV{TMPDIR} ${temporary})
# An allocation over 1 GiB fails (NULL), as on a machine without the memory:
# the readers must report it. Without this, libFuzzer calls any request over
# its memory limit a finding, also one the reader would survive.
set(ENV{ASAN_OPTIONS} "allocator_may_return_null=1:max_allocation_size_mb=1024:detect_leaks=1")
set(ENV{UBSAN_OPTIONS} "print_stacktrace=1:halt_on_error=1")
execute_process(
  COMMAND ${FUZZ_DIR}/fuzz_${HARNESS} -max_total_time=${SECONDS} -max_len=${max_len} -timeout=30 -rss_limit_mb=2048
          -print_final_stats=1 -artifact_prefix=${FUZZ_DIR}/findings/${HARNESS}- ${options} ${corpus} ${seeds}
  INPUT_FILE /dev/null
  OUTPUT_FILE ${log_file}
  ERROR_FILE ${log_file}
  RESULT_VARIABLE result)
file(STRINGS ${log_file} summary REGEX "^(INFO: seed corpus|#[0-9]+.*(INITED|DONE)|Done |stat::|SUMMARY|.*Test unit written)")
foreach(line ${summary})
  message("${line}")
endforeach()
if(NOT result EQUAL 0)
  file(READ ${log_file} log)
  string(LENGTH "${log}" length)
  if(length GREATER 20000)
    math(EXPR start "${length} - 20000")
    string(SUBSTRING "${log}" ${start} -1 log)
  endif()
  message("${log}")
  message(FATAL_ERROR "fuzz_${HARNESS} found a problem (exit ${result}); the input is in ${FUZZ_DIR}/findings/, "
                      "rerun it with ${FUZZ_DIR}/fuzz_${HARNESS} <file>; full log: ${log_file}")
endif()
