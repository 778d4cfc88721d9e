# Depth of field and panoramic cameras (src/scene/camera.c, shaders/common/
# camera.glsl): the thin lens' blur of an edge against the analytic circle of
# confusion, an equirectangular camera's mapping and a fisheye's circle, on
# the GPU and in the reference (tests/camera_check.py). Skips without a device.
if(Python3_Interpreter_FOUND)
  add_test(NAME camera_dof_pano
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/camera_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/camera_check)
  set_tests_properties(camera_dof_pano PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 600
                       PASS_REGULAR_EXPRESSION "all checks passed")
endif()
