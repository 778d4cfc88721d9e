# photonbridge view under Xvfb (tests/view_check.py), one test per part so
# that ctest -j runs them side by side. X11, GLFW and the driver's window
# system code are not ASan-instrumented: no-sanitize keeps them out of the
# ASan pass (the viewer's own code is the CPU part the other parts test).
# RESOURCE_LOCK xvfb: two `xvfb-run -a` started at once can pick the same
# free display number and one of them fails to start its server (seen here
# under ctest -j2: view_errors exited 1 instead of 2), so the tests that start
# an X server (these and blender_viewport) take turns.
foreach(part still input resize nodisplay errors in_flight tracer noise)
  add_test(NAME view_${part}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/view_check.py ${PB_EXE} ${PB_ROOT}
                   ${CMAKE_CURRENT_BINARY_DIR}/view_${part} ${part})
  set_tests_properties(view_${part} PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;view;no-sanitize" TIMEOUT 600
                       RESOURCE_LOCK xvfb)
endforeach()

# The display-only readback (tests/unit/test_gpu_view_readback.c):
# a sequence read back as `view` (no AOV) and `serve` (the beauty) set it,
# against the full readback of `render --frames`: bytes per frame under a
# bound, the same picture. Validation layers on.
if(TEST test_gpu_view_readback)
  set_tests_properties(test_gpu_view_readback PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       LABELS "gpu;no-sanitize;view" TIMEOUT 600)
endif()
