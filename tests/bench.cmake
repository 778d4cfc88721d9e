# The speed-against-error benchmark (issue 8): the driver end to end in its
# smoke mode, the fixed leaf-size threshold on the GPU, and the new render
# options' bounds. Device tests: validation layers fatal, skip without one.
if(TEST test_gpu_lbvh_leaf)
  set_tests_properties(test_gpu_lbvh_leaf PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       LABELS "gpu;no-sanitize" TIMEOUT 600)
endif()
find_program(PB_BENCH_PYTHON NAMES python3)
if(PB_BENCH_PYTHON)
  add_test(NAME bench_smoke
           COMMAND ${PB_BENCH_PYTHON} ${PB_ROOT}/tests/bench_smoke.py ${PB_EXE}
                   ${CMAKE_CURRENT_BINARY_DIR}/bench_smoke
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(bench_smoke PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize;bench" TIMEOUT 900
                       PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed")
endif()
add_test(NAME cli_render_leaf_size_zero
         COMMAND sh -c "\"$0\" render samples/cornell_box/cornell_box.gltf -o x.exr --leaf-size 0; echo \"exit=$?\""
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_leaf_size_zero PROPERTIES PASS_REGULAR_EXPRESSION "leaf-size.*exit=2")
add_test(NAME cli_render_leaf_size_over
         COMMAND sh -c "\"$0\" render samples/cornell_box/cornell_box.gltf -o x.exr --leaf-size 4097; echo \"exit=$?\""
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_leaf_size_over PROPERTIES PASS_REGULAR_EXPRESSION "leaf-size.*exit=2")
