# The density estimators behind one interface (render/estimate/estimator.h):
# tests/estimator_check.py. Device tests: validation layers fatal, skip
# without a device.
add_test(NAME estimator_interface
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/estimator_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/estimator_check interface)
set_tests_properties(estimator_interface PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 600)
# kNN photon mapping (seed 000 3.1): tests/unit/test_gpu_knn.c.
if(TEST test_gpu_knn)
  set_tests_properties(test_gpu_knn PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       LABELS "gpu;no-sanitize" TIMEOUT 600)
endif()
add_test(NAME estimator_knn_cli
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/estimator_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/estimator_check knn)
set_tests_properties(estimator_knn_cli PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 600)
# kNN at the default k on spot_room: no pixel lit by the gather black (the llvmpipe
# loop limiter; shaders/estimate/knn.comp SC_BUDGET).
add_test(NAME estimator_knn_spot_room
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/estimator_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/estimator_check knn_spot)
set_tests_properties(estimator_knn_spot_room PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 600)
# Every estimator renders every sample, and a closed furnace (a box of albedo 0.6 around a point
# light) against the reference path tracer (tests/estimator_check.py part_samples, part_furnace).
add_test(NAME estimator_samples
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/estimator_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/estimator_check samples)
set_tests_properties(estimator_samples PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 900)
add_test(NAME estimator_furnace
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/estimator_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/estimator_check furnace)
set_tests_properties(estimator_furnace PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 900)
# The numerical hard cases (tests/hard/hard_cases.py: scale 1e-3 .. 1e3, far
# from the origin, grazing light, degenerate triangles, extreme lights and
# albedos) with kNN: finite everywhere, the same picture as kNN's own
# cornell_box. The validation layers (fatal) on kNN's plain pair and on the
# cases that leave its maps empty (--validate cornell,materials); every
# case runs under them with the default estimator in hard_cases_gpu.
if(Python3_Interpreter_FOUND)
  add_test(NAME hard_cases_gpu_knn
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/hard/hard_cases.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/hard_gpu_knn --renderer gpu --gpu-args "--estimator knn"
                   --validate cornell,materials
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(hard_cases_gpu_knn PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       LABELS "gpu;no-sanitize;hard" TIMEOUT 900)
endif()
