# libFuzzer harnesses, built alone in their own clang build (the top-level
# CMakeLists.txt includes this file, and nothing else, with -DGMON_FUZZ=ON):
# the scene reader with conversion and BVH, the PLY reader, the EXR reader,
# the image readers (textures and lights' images).
# No OpenCL. tests/fuzz/build_fuzzers.cmake and run_fuzzer.cmake build and
# run them for the test suite; docs/design.md's developer options say how to run
# them longer by hand.
if(NOT CMAKE_C_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "GMON_FUZZ needs clang: configure with -DCMAKE_C_COMPILER=clang")
endif()
find_package(OpenEXR 3 CONFIG REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(CGLM REQUIRED IMPORTED_TARGET cglm)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
pkg_check_modules(BLOSC REQUIRED IMPORTED_TARGET blosc)
find_library(MATH_LIBRARY m REQUIRED)
find_package(ZLIB REQUIRED)

# Everything is instrumented for coverage and checked by ASan and UBSan; only
# the harnesses link libFuzzer's main.
set(FUZZ_SANITIZE -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
add_compile_options(${FUZZ_SANITIZE} -fsanitize=fuzzer-no-link)
add_link_options(${FUZZ_SANITIZE})

add_library(fuzz_code STATIC
  ${GMON_SCENE_SOURCES}
  host/render/scene_convert.c
  host/render/render_scene.c
  host/render/light_tree_build.c
  host/render/render_textures.c
  host/render/pixel_filter.c
  host/render/bvh.c
  host/io/exr_image.c
  host/io/image_read.c
  host/io/image_probe.c
  tests/fuzz/fuzz_input.c)
target_include_directories(fuzz_code PUBLIC host kernels/common kernels/film kernels/tracing ${GMON_GENERATED_DIR}/kernels/film
                                            ${GMON_GENERATED_DIR}/kernels/tracing tests/fuzz)
add_dependencies(fuzz_code sorting_networks)
target_link_libraries(fuzz_code PUBLIC PkgConfig::CGLM PkgConfig::STB PkgConfig::BLOSC OpenEXR::OpenEXRCore ZLIB::ZLIB
                      ${MATH_LIBRARY})

foreach(harness scene ply exr image)
  add_executable(fuzz_${harness} tests/fuzz/fuzz_${harness}.c)
  target_link_libraries(fuzz_${harness} PRIVATE fuzz_code)
  target_link_options(fuzz_${harness} PRIVATE -fsanitize=fuzzer)
endforeach()

add_executable(make_exr_seeds tests/fuzz/make_exr_seeds.c)
target_link_libraries(make_exr_seeds PRIVATE fuzz_code)
