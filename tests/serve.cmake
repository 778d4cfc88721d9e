# photonbridge serve, the persistent session (tests/serve_check.py): one
# test per part (protocol, still: equal to render --frames, kill: no process
# outlives its client, tracer: --tracer and the "tracer" setting, private:
# the session folder 0700, its files 0600, nothing followed or left; noise:
# a stream rests at its noise threshold). Each skips (77) without a Vulkan device. no-sanitize
# as the other CLI GPU tests (lavapipe leaks 128 bytes LSan cannot name).
foreach(part protocol still tracer kill private noise)
  add_test(NAME serve_${part}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/serve_check.py ${PB_EXE} ${PB_ROOT}
                   ${CMAKE_CURRENT_BINARY_DIR}/serve_${part} ${part})
  set_tests_properties(serve_${part} PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;serve;no-sanitize" TIMEOUT 600)
endforeach()
