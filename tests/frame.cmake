# The GPU-resident frame: the resolve pass and readback give the
# same pixels as the host resolve, for every sample scene and a sequence
# (tests/frame_same_pixels.py); with -DPB_BASELINE_EXE=/path/to/photonbridge
# (a build of an earlier commit) also the same pixels as that binary.
set(PB_BASELINE_EXE "" CACHE FILEPATH "photonbridge binary of an earlier commit for frame_same_pixels_*")
foreach(part samples extra in_flight still_gpu)
  add_test(NAME frame_same_pixels_${part}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/frame_same_pixels.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/frame_same_pixels_${part} "${PB_BASELINE_EXE}" ${part})
  set_tests_properties(frame_same_pixels_${part} PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 600)
endforeach()
# No host round trip inside the filter chain: per-frame transfers in --json
# (tests/frame_transfers.py).
add_test(NAME frame_transfers
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/frame_transfers.py ${PB_EXE} ${PB_ROOT}
                 ${CMAKE_CURRENT_BINARY_DIR}/frame_transfers)
set_tests_properties(frame_transfers PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 600)
# Frames in flight (gpu.h PB_GPU_FRAMES): synchronization validation over
# in-flight sequences gives zero messages, and the next frame's recording
# overlaps the previous frame's last submission (tests/frame_in_flight.py).
add_test(NAME frame_in_flight
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/frame_in_flight.py ${PB_EXE} ${PB_ROOT}
                 ${CMAKE_CURRENT_BINARY_DIR}/frame_in_flight)
set_tests_properties(frame_in_flight PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 900)
# The frame reads as its stages: no function in src/render over 150 lines
# (tests/function_length.py; GPU-free).
add_test(NAME frame_function_length
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/function_length.py ${PB_ROOT}/src/render 150)
# The house's layout from the includes: nothing below src/app includes it,
# the rooms' include graph and the headers have no cycle, src/render and
# shaders/ one level deeper by concern (tests/layout_check.py; GPU-free).
add_test(NAME layout_rooms COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/layout_check.py ${PB_ROOT})
set_tests_properties(layout_rooms PROPERTIES PASS_REGULAR_EXPRESSION "[0-9]+ passed, 0 failed")
