# The speed-against-error benchmark: the driver end to end in its
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
# The sequence benchmark's deformation part (bench/run_sequences.py
# --deform-only) on three frames: every vertex of the skinned mesh posed per
# frame, none of the static one, which never updates its GPU scene.
if(PB_BENCH_PYTHON)
  add_test(NAME bench_deform_smoke
           COMMAND sh -c "\"$1\" info --devices >/dev/null 2>&1 || { echo 'skip: no Vulkan device'; exit 77; };
                          d='${CMAKE_CURRENT_BINARY_DIR}/bench_deform_smoke'; rm -rf \"$d\" && mkdir -p \"$d\" &&
                          \"$0\" bench/run_sequences.py --exe \"$1\" --deform-only --deform-frames 0:2 --out \"$d\" >\"$d/log\" 2>&1 || { cat \"$d/log\"; exit 1; };
                          \"$0\" -c \"import json,sys; r={x['mode']: x for x in json.load(open(sys.argv[1]))['rows']}; s, t, g = r['skinned'], r['static'], r['rigid'];
ok = [s['posed_per_frame'] == s['vertices'] == s['skinned'] == s['morphed'] > 50000, s['scene_update_ms'] > 0, g['scene_update_ms'] > 0,
      t['posed_per_frame'] == 0 and t['scene_update_ms'] == 0, s['triangles'] == 100000];
print(ok); print('%d passed, %d failed' % (sum(ok), len(ok) - sum(ok)))\" \"$d/deform.json\""
                   ${PB_BENCH_PYTHON} ${PB_EXE}
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(bench_deform_smoke PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize;bench" TIMEOUT 600
                       PASS_REGULAR_EXPRESSION "5 passed, 0 failed")
endif()
