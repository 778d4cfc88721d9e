# Hard cases for numerical stability: tests/hard/hard_cases.py
# generates the scenes, renders them through the CLI and checks the pictures;
# exr_probe dumps an EXR's channels as JSON for it. The reference half runs
# under the sanitizers too; the GPU half opens a Vulkan device (validation
# layers fatal, skipped without a device). hard_cases_gpu renders every case
# under the validation layers; the runs through the other estimators (here
# and hard_cases_gpu_knn in tests/estimator.cmake) have them on the plain
# pair and on the cases that leave the maps empty (--validate
# cornell,materials: black surfaces, no lights), where an estimator's own
# passes meet zero-sized buffers; their other cases check the pictures.
add_executable(exr_probe ${PB_ROOT}/tests/hard/exr_probe.c)
target_compile_options(exr_probe PRIVATE ${PB_C_WARN})
target_link_libraries(exr_probe PRIVATE pb)
if(Python3_Interpreter_FOUND)
  foreach(kind ref gpu)
    add_test(NAME hard_cases_${kind}
             COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/hard/hard_cases.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                     ${CMAKE_CURRENT_BINARY_DIR}/hard_${kind} --renderer ${kind}
             WORKING_DIRECTORY ${PB_ROOT})
  endforeach()
  # The same GPU cases through the screen-space splatting estimator
  # (no non-finite values on the hard cases, the same pictures).
  add_test(NAME hard_cases_gpu_splat
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/hard/hard_cases.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/hard_gpu_splat --renderer gpu --gpu-args "--estimator splat"
                   --validate cornell,materials
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(hard_cases_gpu_splat PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       LABELS "gpu;no-sanitize;hard" TIMEOUT 900)
  set_tests_properties(hard_cases_ref PROPERTIES TIMEOUT 900 LABELS hard)
  set_tests_properties(hard_cases_gpu PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       LABELS "gpu;no-sanitize;hard" TIMEOUT 900)
  # The GPU half again through the view-sample cluster hierarchy (seed 004,
  # render --estimator vsch), both of its variants.
  foreach(variant vsch vsch_directional)
    if(variant STREQUAL "vsch")
      set(extra "--estimator vsch")
    else()
      set(extra "--estimator vsch --vsch-directional")
    endif()
    add_test(NAME hard_cases_gpu_${variant}
             COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/hard/hard_cases.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                     ${CMAKE_CURRENT_BINARY_DIR}/hard_gpu_${variant} --renderer gpu --gpu-args ${extra}
                     --validate cornell,materials
             WORKING_DIRECTORY ${PB_ROOT})
    set_tests_properties(hard_cases_gpu_${variant} PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                         LABELS "gpu;no-sanitize;hard" TIMEOUT 900)
  endforeach()
endif()
