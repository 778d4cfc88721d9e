# Benchmark peers: LuxCoreRender (pyluxcore) and Mitsuba 3 read the scene
# through `export-peer` (src/peer/peer.h; docs/peers.md).
#   test_peer_render   (unit-test glob; peer_render_mitsuba_llvm: the same in
#                      Mitsuba's llvm_ad_rgb) each peer's render of the analytic
#                      planes (point, sun, spot) within 1 % of the radiance;
#                      needs tools/luxcore and tools/mitsuba3 and FAILS
#                      without them (scripts/install-deps.sh installs them)
#   peer_dump_X_F      every committed sample dumps in format F: PLY headers,
#                      vertex and triangle counts against the loader's
#                      (tests/peer_dump_check.py), the scene file's references
#   peer_sample_X_F    the same, then the peer renders it (32 px, 4 samples):
#                      accepted, finite, not black; FAILS without the venv
#   cli_export_peer_*  command-line errors
set_tests_properties(test_peer_render PROPERTIES LABELS "peers;no-sanitize" TIMEOUT 600
                     PASS_REGULAR_EXPRESSION " 0 failed")

set(PB_PEER_PYTHON_luxcore "${PB_ROOT}/tools/luxcore/bin/python")
set(PB_PEER_PYTHON_mitsuba "${PB_ROOT}/tools/mitsuba3/bin/python")
if(Python3_Interpreter_FOUND)
  file(GLOB PB_PEER_SAMPLES ${PB_ROOT}/samples/*/*.gltf)
  foreach(scene ${PB_PEER_SAMPLES})
    get_filename_component(sname ${scene} NAME_WE)
    foreach(fmt luxcore mitsuba)
      add_test(NAME peer_dump_${sname}_${fmt}
               COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/peer_dump_check.py ${PB_EXE} ${scene} ${fmt}
                       ${CMAKE_CURRENT_BINARY_DIR}/peer_dump/${sname}_${fmt}
               WORKING_DIRECTORY ${PB_ROOT})
      set_tests_properties(peer_dump_${sname}_${fmt} PROPERTIES LABELS peers TIMEOUT 120
                           PASS_REGULAR_EXPRESSION " 0 failed")
      add_test(NAME peer_sample_${sname}_${fmt}
               COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/peer_dump_check.py ${PB_EXE} ${scene} ${fmt}
                       ${CMAKE_CURRENT_BINARY_DIR}/peer_sample/${sname}_${fmt} --render ${PB_PEER_PYTHON_${fmt}}
               WORKING_DIRECTORY ${PB_ROOT})
      set_tests_properties(peer_sample_${sname}_${fmt} PROPERTIES LABELS "peers;no-sanitize" TIMEOUT 300
                           PASS_REGULAR_EXPRESSION " 0 failed")
    endforeach()
  endforeach()
endif()

pb_cli_test(cli_export_peer_no_format export-peer samples/cornell_box/cornell_box.gltf -o x EXIT 2
            REGEX "expected SCENE, --format luxcore\\|mitsuba and -o DIR.*exit=2")
pb_cli_test(cli_export_peer_bad_format export-peer samples/cornell_box/cornell_box.gltf -o x --format pbrt
            EXIT 2 REGEX "unknown value 'pbrt'.*exit=2")
pb_cli_test(cli_export_peer_missing export-peer does-not-exist.gltf --format mitsuba -o x EXIT 3
            REGEX "does-not-exist.gltf: cannot open.*exit=3")
pb_cli_test(cli_export_peer_no_parent export-peer samples/cornell_box/cornell_box.gltf --format luxcore
            -o /nonexistent-dir/sub EXIT 3 REGEX "/nonexistent-dir/sub: cannot create the folder.*exit=3")
pb_cli_test(cli_export_peer_area_light export-peer tests/data/lights/area_square/area_square.gltf --format mitsuba
            -o x EXIT 6 REGEX "lights\\[[0-9]+\\] '[^']*': area lights are not written to Mitsuba 3.*exit=6")
pb_cli_test(cli_export_peer_soft_light export-peer tests/data/lights/point_soft/point_soft.gltf --format luxcore
            -o x EXIT 6 REGEX "lights\\[[0-9]+\\] '[^']*': a soft light \\(radius [0-9.]+\\) is not written to LuxCore.*exit=6")
pb_cli_test(cli_export_peer_world_map export-peer tests/data/lights/world_hdri/world_hdri.gltf --format luxcore
            -o x EXIT 6 REGEX "world '[^']*': an environment map is not written to LuxCore.*exit=6")

# Mitsuba's vectorised CPU variant (Dr.Jit on the system's libLLVM: libllvm19
# from install-deps) on the same planes.
add_test(NAME peer_render_mitsuba_llvm COMMAND test_peer_render mitsuba WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(peer_render_mitsuba_llvm PROPERTIES ENVIRONMENT "PB_MITSUBA_VARIANT=llvm_ad_rgb"
                     LABELS "peers;no-sanitize" TIMEOUT 600 PASS_REGULAR_EXPRESSION " 0 failed")

# The peers' part of the benchmark (bench/run_peers.py --mode tiny: cornell_box,
# 32 px, a few samples each for the Embree reference, LuxCore PhotonGI and
# BIDIRVMCPU, Mitsuba 3 and Cycles 4.5, HDR-FLIP beside PSNR) and structural
# checks on its results.json (tests/bench_peers_check.py): every peer's image
# finite, the fields there, more samples scoring higher. Needs tools/luxcore,
# tools/mitsuba3, tools/bpy45 and tools/flip (scripts/install-deps.sh) and
# FAILS without them.
if(Python3_Interpreter_FOUND)
  add_test(NAME bench_peers_tiny
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/bench_peers_check.py ${PB_EXE}
                   ${CMAKE_CURRENT_BINARY_DIR}/bench_peers_tiny
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(bench_peers_tiny PROPERTIES LABELS "peers;no-sanitize" TIMEOUT 300
                       PASS_REGULAR_EXPRESSION " 0 failed")
endif()
