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
# The paths written are printed even with --quiet (a scene may name them).
if(NOT err MATCHES "wrote [^\n]*cli-render.exr and [^\n]*cli-render.png")
  message(FATAL_ERROR "the paths written are not printed: '${err}'")
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
# --dump-kernel writes the specialized path tracer with its defines; the
# summary reports every device.
execute_process(COMMAND ${COMMAND} --spp 2 --resolution 8x8 --estimators mean --dump-kernel ${out}-kernel.cl
                        --outfile ${out}-dump.exr ${SCENE}
                RESULT_VARIABLE code OUTPUT_VARIABLE summary ERROR_VARIABLE err)
if(NOT code EQUAL 0 OR NOT EXISTS ${out}-kernel.cl)
  message(FATAL_ERROR "render with --dump-kernel failed (${code}): ${err}")
endif()
file(READ ${out}-kernel.cl kernel)
if(NOT kernel MATCHES "#define GMON_FEATURES 0x[0-9a-f]+" OR NOT kernel MATCHES "#define EST_SETS 1\n"
   OR NOT kernel MATCHES "render_samples")
  message(FATAL_ERROR "the dumped kernel lacks its defines or its kernel")
endif()
if(NOT summary MATCHES "device 0 '[^']+': 100.0% of samples" OR NOT summary MATCHES "MiB allocated")
  message(FATAL_ERROR "the summary lacks the per-device line: ${summary}")
endif()
# A device index that does not exist: one clear line, exit 2 (a bad flag),
# before the scene loads (this one does not exist).
execute_process(COMMAND ${COMMAND} --device 99 --outfile ${out}-none.exr /nonexistent/scene.pbrt RESULT_VARIABLE code
                ERROR_VARIABLE err)
if(NOT code EQUAL 2 OR NOT err MATCHES "no device 99" OR err MATCHES "nonexistent")
  message(FATAL_ERROR "--device 99: exit ${code}, '${err}'")
endif()
# A checkpoint that cannot be written (a directory stands in its place) is an
# error, and the render goes on: later checkpoints and --outfile are written,
# exit 1.
file(REMOVE_RECURSE ${out}-checkpoints)
file(REMOVE ${out}-checkpoints.exr)
file(MAKE_DIRECTORY ${out}-checkpoints/spp-000001.exr)
execute_process(COMMAND ${COMMAND} --spp 4 --resolution 8x8 --quiet --checkpoints ${out}-checkpoints
                        --outfile ${out}-checkpoints.exr ${SCENE}
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 1 OR NOT err MATCHES "spp-000001.exr" OR NOT EXISTS ${out}-checkpoints.exr
   OR NOT EXISTS ${out}-checkpoints/spp-000004.exr)
  message(FATAL_ERROR "a failed checkpoint: exit ${code}, '${err}'")
endif()
# The output directory is checked before the render: no checkpoint is made.
file(REMOVE_RECURSE ${out}-unused)
execute_process(COMMAND ${COMMAND} --spp 4 --resolution 8x8 --checkpoints ${out}-unused
                        --outfile ${out}-missing/image.exr ${SCENE}
                RESULT_VARIABLE code ERROR_VARIABLE err)
if(NOT code EQUAL 1 OR NOT err MATCHES "cannot write [^\n]*-missing/image.exr" OR EXISTS ${out}-unused)
  message(FATAL_ERROR "a missing output directory: exit ${code}, '${err}'")
endif()
