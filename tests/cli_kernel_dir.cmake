# Kernels read at run time from a directory (--kernel-dir, GMON_KERNEL_DIR)
# build, with the sorting networks the build generated, and render the very
# image the embedded kernels render.
# cmake -DCOMMAND=<gmonrt> -DSCENE=<scene> -DKERNEL_DIR=<repo>/kernels -DWORK_DIR=<dir> -P cli_kernel_dir.cmake
set(out ${WORK_DIR}/cli-kernel-dir)
set(args --spp 8 --resolution 16x12 --sets 5 --write-sets --quiet)
foreach(source embedded flag environment)
  file(REMOVE ${out}-${source}.exr)
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=GMON_KERNEL_DIR ${COMMAND} ${args}
                        --outfile ${out}-embedded.exr ${SCENE}
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "render with the embedded kernels failed (${code}): ${err}")
endif()
execute_process(COMMAND ${COMMAND} ${args} --kernel-dir ${KERNEL_DIR} --outfile ${out}-flag.exr ${SCENE}
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "render with --kernel-dir ${KERNEL_DIR} failed (${code}): ${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E env GMON_KERNEL_DIR=${KERNEL_DIR} ${COMMAND} ${args}
                        --outfile ${out}-environment.exr ${SCENE}
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  message(FATAL_ERROR "render with GMON_KERNEL_DIR=${KERNEL_DIR} failed (${code}): ${err}")
endif()
foreach(source flag environment)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${out}-embedded.exr ${out}-${source}.exr
                  RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "${out}-${source}.exr differs from the render with the embedded kernels")
  endif()
endforeach()
