# The Blender materials against Cycles 3.4 (tests/principled_lobes.py): each
# Principled lobe alone, a rough glass and the white furnace, rendered by the
# reference and by the GPU pipeline and compared with the committed Cycles
# renders of tests/data/principled (exporters/blender/make_principled_tests.py):
# mean within 1 %, PSNR >= 35 dB.
if(Python3_Interpreter_FOUND)
  add_test(NAME principled_lobes_ref
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/principled_lobes.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/principled_ref --renderer ref
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(principled_lobes_ref PROPERTIES TIMEOUT 600 LABELS principled
                       PASS_REGULAR_EXPRESSION " 0 failed")
  add_test(NAME principled_lobes_gpu
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/principled_lobes.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/principled_gpu --renderer gpu
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(principled_lobes_gpu PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       TIMEOUT 1200 LABELS "gpu;no-sanitize;principled" PASS_REGULAR_EXPRESSION " 0 failed")
endif()
