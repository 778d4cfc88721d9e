# Blender's viewport in photonbridge mode, with Blender's window under
# xvfb-run (tests/blender/viewport_check.py): the drawn picture equals the
# CLI render of that view within noise. Skips (77) without Blender, xvfb-run
# or a Vulkan device.
add_test(NAME blender_viewport
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/blender/viewport_check.py ${PB_EXE} ${PB_ROOT}
                 ${CMAKE_CURRENT_BINARY_DIR}/blender_viewport)
set_tests_properties(blender_viewport PROPERTIES SKIP_RETURN_CODE 77 LABELS "blender;gpu;no-sanitize" TIMEOUT 900
                     RESOURCE_LOCK xvfb)  # one X server starting at a time (tests/view.cmake)
