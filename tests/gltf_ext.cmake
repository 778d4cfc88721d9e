# What Blender's glTF exporter writes beyond the core (tests/data/gltf_ext,
# issue 16): COLOR_0, KHR_texture_transform and TEXCOORD_1, unlit, volume,
# blend-0 spots, Blender's default surface.
#   test_deform          (unit-test glob) skins and morph targets posed on the CPU
#   test_gpu_gltf_ext    (unit-test glob, tests/gpu.cmake) GPU and reference renders
#   test_pov_gltf_ext    (unit-test glob) export-pov through POV-Ray
#   gltf_ext_scenes_fresh  the committed scenes are what make_scenes.py writes
set_tests_properties(test_pov_gltf_ext PROPERTIES LABELS "povray;no-sanitize" SKIP_RETURN_CODE 77 TIMEOUT 300)
if(Python3_Interpreter_FOUND)
  set(PB_GLTF_EXT_FRESH ${CMAKE_CURRENT_BINARY_DIR}/gltf_ext_fresh)
  add_test(NAME gltf_ext_scenes_fresh
           COMMAND sh -c "rm -rf \"$1\" && \"$2\" \"$3/tests/data/gltf_ext/make_scenes.py\" \"$1\" &&
                          for f in \"$3\"/tests/data/gltf_ext/*.gltf \"$3\"/tests/data/gltf_ext/*.png; do
                            cmp \"$f\" \"$1/$(basename \"$f\")\" || exit 1; done; echo '1 passed, 0 failed'"
                   fresh ${PB_GLTF_EXT_FRESH} ${Python3_EXECUTABLE} ${PB_ROOT})
  set_tests_properties(gltf_ext_scenes_fresh PROPERTIES PASS_REGULAR_EXPRESSION "1 passed, 0 failed")
endif()
