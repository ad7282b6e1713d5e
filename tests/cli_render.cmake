# gmonrt end to end: render a small scene with every layer, then re-estimate
# it with another Gini mode; both must succeed and write EXR and PNG.
set(out ${WORK_DIR}/cli-render)
file(REMOVE ${out}.exr ${out}.png ${out}-estimate.exr ${out}-estimate.png)
execute_process(COMMAND ${COMMAND} --spp 8 --resolution 16x12 --sets 4 --diagnostics --write-sets --quiet
                        --outfile ${out}.exr ${SCENE}
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0 OR NOT EXISTS ${out}.exr OR NOT EXISTS ${out}.png)
  message(FATAL_ERROR "render failed (${code}): ${err}")
endif()
execute_process(COMMAND ${COMMAND} estimate --gini-mode luminance --quiet --outfile ${out}-estimate.exr ${out}.exr
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 0 OR NOT EXISTS ${out}-estimate.exr OR NOT EXISTS ${out}-estimate.png)
  message(FATAL_ERROR "estimate failed (${code}): ${err}")
endif()
# Without --write-sets there is nothing to re-estimate: a clear error.
execute_process(COMMAND ${COMMAND} estimate ${out}-estimate.exr RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 1 OR NOT err MATCHES "write-sets")
  message(FATAL_ERROR "estimate of a file without sets: exit ${code}, '${err}'")
endif()
