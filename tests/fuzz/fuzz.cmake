# libFuzzer targets for the glTF/GLB loader, the EXR reader and the image
# decoders.
#
# Included by the top-level CMakeLists.txt when PB_FUZZ=ON, in a build tree of
# its own configured with clang (`make fuzz-quick` does it):
#   CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -DPB_FUZZ=ON -DPB_WERROR=ON
# Such a tree builds only what the targets need (src/core, src/scene,
# src/image), instrumented for libFuzzer with ASan + UBSan; tests/fuzz/run.sh
# runs them.
#
#   fuzz_gltf       pb_scene_load_memory on the input (no file written)
#   fuzz_exr        pb_exr_read on the input
#   fuzz_image      the decoder the input's signature picks (PNG, JPEG, EXR)
#   fuzz_exr_seeds  writes the EXR seed files (every compression, tiled, ...)
if(NOT CMAKE_C_COMPILER_ID MATCHES "Clang" OR NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "PB_FUZZ needs clang for both C and C++ (libFuzzer): "
          "configure with CC=clang-14 CXX=clang++-14")
endif()

find_package(Threads REQUIRED)
find_package(OpenEXR 3 REQUIRED)

set(PB_FUZZ_SAN -fsanitize=address,undefined -fno-sanitize-recover=undefined
                -fno-omit-frame-pointer -g)

file(GLOB PB_FUZZ_LIB_SOURCES CONFIGURE_DEPENDS
     ${CMAKE_SOURCE_DIR}/src/core/*.c ${CMAKE_SOURCE_DIR}/src/scene/*.c
     ${CMAKE_SOURCE_DIR}/src/scene/*.cpp ${CMAKE_SOURCE_DIR}/src/image/*.c)
add_library(pb_fuzzlib STATIC ${PB_FUZZ_LIB_SOURCES})
# shaders/: the camera view struct (shared/pb_gpu.h) that src/scene/camera.h
# shares with the GPU.
target_include_directories(pb_fuzzlib PUBLIC ${CMAKE_SOURCE_DIR}/src ${CMAKE_BINARY_DIR}/generated
                           ${CMAKE_SOURCE_DIR}/shaders PRIVATE /usr/include/stb)
target_compile_definitions(pb_fuzzlib PUBLIC _GNU_SOURCE)
target_compile_options(pb_fuzzlib PRIVATE
  $<$<COMPILE_LANGUAGE:C>:${PB_C_WARN}>
  $<$<COMPILE_LANGUAGE:CXX>:${PB_WARN}>
  PUBLIC ${PB_FUZZ_SAN} -fsanitize=fuzzer-no-link)
target_link_options(pb_fuzzlib PUBLIC -fsanitize=address,undefined)
target_link_libraries(pb_fuzzlib PUBLIC OpenEXR::OpenEXRCore PkgConfig::SPNG JPEG::JPEG Threads::Threads m)

# The targets' shared set-up (temporary folder, input files, contracts).
add_library(pb_fuzz_util STATIC ${CMAKE_SOURCE_DIR}/tests/fuzz/fuzz_util.c)
target_compile_options(pb_fuzz_util PRIVATE ${PB_C_WARN})
target_link_libraries(pb_fuzz_util PUBLIC pb_fuzzlib)
foreach(t gltf exr image)
  add_executable(fuzz_${t} ${CMAKE_SOURCE_DIR}/tests/fuzz/fuzz_${t}.c)
  target_compile_options(fuzz_${t} PRIVATE ${PB_C_WARN} -fsanitize=fuzzer)
  target_link_options(fuzz_${t} PRIVATE -fsanitize=fuzzer)
  target_link_libraries(fuzz_${t} PRIVATE pb_fuzz_util pb_fuzzlib)
endforeach()
# Files the loader may reference next to the input (base.bin, tex.png).
target_compile_definitions(fuzz_gltf PRIVATE
  PB_FUZZ_AUX_DIR="${CMAKE_SOURCE_DIR}/tests/corpus/valid/base")

# A plain program (no libFuzzer main) that writes the EXR seeds.
add_executable(fuzz_exr_seeds ${CMAKE_SOURCE_DIR}/tests/fuzz/exr_seeds.c)
target_compile_options(fuzz_exr_seeds PRIVATE ${PB_C_WARN})
target_link_libraries(fuzz_exr_seeds PRIVATE OpenEXR::OpenEXRCore m)

# Replays of the kept regression inputs and the seeds, so that a fixed crash
# stays fixed (ctest in this build tree; the timed runs are tests/fuzz/run.sh).
enable_testing()
add_test(NAME fuzz_replay
         COMMAND bash ${CMAKE_SOURCE_DIR}/tests/fuzz/run.sh --replay ${CMAKE_BINARY_DIR})
