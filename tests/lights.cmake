# Each kind of light (area, soft point, soft spot, soft sun) and the world
# (a colour, an HDR map) against the committed Cycles 3.4 renders of
# tests/data/lights (exporters/blender/light_scenes.py): the reference within
# both images' noise, the GPU pipeline above 30 dB (tests/lights_cycles.py).
# exr_probe comes from tests/hard.cmake.
if(Python3_Interpreter_FOUND)
  set(PB_LIGHTS_WORK ${CMAKE_CURRENT_BINARY_DIR}/lights_cycles)
  add_test(NAME lights_cycles_ref
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/lights_cycles.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${PB_ROOT}/tests/data/lights ${PB_LIGHTS_WORK} ref)
  set_tests_properties(lights_cycles_ref PROPERTIES LABELS no-sanitize TIMEOUT 600)
  add_test(NAME lights_cycles_gpu
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/lights_cycles.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${PB_ROOT}/tests/data/lights ${PB_LIGHTS_WORK} gpu)
  set_tests_properties(lights_cycles_gpu PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       LABELS "gpu;no-sanitize" TIMEOUT 900)
endif()
