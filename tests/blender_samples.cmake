# The .blend samples of samples/blender (exporters/blender/blend_samples.py:
# metal and plastic under soft lights, an HDRI-lit scene, a Principled glass
# ball under a soft spot) handed over by the Blender render engine's writer
# (the committed hand-off without Blender) and rendered by the reference and
# the GPU against the committed Cycles 3.4 renders (tests/blender_samples.py:
# mean and PSNR thresholds from the measured values, docs/benchmarks.md,
# "Blender's materials against Cycles 3.4"). exr_probe comes from tests/hard.cmake.
if(Python3_Interpreter_FOUND)
  add_test(NAME blender_samples_ref
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/blender_samples.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/blender_samples_ref --renderer ref
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(blender_samples_ref PROPERTIES TIMEOUT 600 LABELS "principled;no-sanitize"
                       PASS_REGULAR_EXPRESSION "3 passed, 0 failed")
  add_test(NAME blender_samples_gpu
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/blender_samples.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/blender_samples_gpu --renderer gpu
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(blender_samples_gpu PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       TIMEOUT 900 LABELS "gpu;no-sanitize;principled" PASS_REGULAR_EXPRESSION "3 passed, 0 failed")
endif()
