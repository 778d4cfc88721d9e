# Seed 003's multi-level up-sampling of the diffuse photon irradiance (sec. 6,
# Figure 9; src/render/estimate/upsample.c): the lit plane with an analytic answer
# (tests/unit/test_gpu_upsample.c) and cornell_box from the command line
# against --upsample-levels 0 (tests/upsample_check.py). Validation layers
# fatal, skip without a device.
if(TEST test_gpu_upsample)
  set_tests_properties(test_gpu_upsample PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       LABELS "gpu;no-sanitize" TIMEOUT 600)
endif()
if(Python3_Interpreter_FOUND)
  add_test(NAME upsample_cornell
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/upsample_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/upsample_check)
  set_tests_properties(upsample_cornell PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 900)
endif()
