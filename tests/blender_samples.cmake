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
# The same scenes saved by Blender 4.5 LTS with Principled v2, light
# temperature / exposure / Normalize off and AgX (samples/blender45,
# exporters/blender/blend_samples45.py), handed over by Blender 4.5's writer
# (tools/bpy45) and rendered at the render engine's defaults against
# Cycles 4.5: at least 30 dB, mean within 2 % (the reference: 33-35 dB, 1 %).
if(Python3_Interpreter_FOUND)
  foreach(pb_r ref gpu)
    add_test(NAME blender45_samples_${pb_r}
             COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/blender_samples.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                     ${CMAKE_CURRENT_BINARY_DIR}/blender45_samples_${pb_r} --renderer ${pb_r} --set 45
             WORKING_DIRECTORY ${PB_ROOT})
  endforeach()
  set_tests_properties(blender45_samples_ref PROPERTIES TIMEOUT 900 LABELS "principled;no-sanitize"
                       ENVIRONMENT "PB_BLENDER_PYTHON=${PB_ROOT}/tools/bpy45/bin/python"
                       PASS_REGULAR_EXPRESSION "3 passed, 0 failed")
  set_tests_properties(blender45_samples_gpu PROPERTIES TIMEOUT 1200 LABELS "gpu;no-sanitize;principled"
                       ENVIRONMENT "PB_VK_VALIDATION=1;PB_BLENDER_PYTHON=${PB_ROOT}/tools/bpy45/bin/python"
                       SKIP_RETURN_CODE 77 PASS_REGULAR_EXPRESSION "3 passed, 0 failed")
endif()
