# The density estimators behind one interface (issue 19; render/estimator.h):
# tests/estimator_check.py. Device tests: validation layers fatal, skip
# without a device.
add_test(NAME estimator_interface
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/estimator_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/estimator_check interface)
set_tests_properties(estimator_interface PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 600)
