# photonbridge batch: render jobs in one process, the device and its pipeline
# cache shared (tests/batch_check.py: pictures equal to render's, pipelines
# reused, per-job exit codes, broken job files). Skips (77) without a Vulkan
# device; no-sanitize as the other CLI GPU tests (lavapipe leaks 128 bytes
# LSan cannot name).
add_test(NAME batch_cli
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/batch_check.py ${PB_EXE} ${CMAKE_CURRENT_BINARY_DIR}/batch_cli)
set_tests_properties(batch_cli PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 900
                     PASS_REGULAR_EXPRESSION "\n0 failed\n")
