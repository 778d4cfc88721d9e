# What Blender's glTF exporter writes beyond the core (tests/data/gltf_ext):
# COLOR_0, KHR_texture_transform and TEXCOORD_1, unlit, volume,
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

# The skin and shape-key scene (tests/data/deform, test_deform_blender): when
# Blender is installed, re-export it and compare by content (skins, morph
# targets, animations and the baked frames included); skipped without.
find_program(PB_BLENDER_DEFORM blender)
if(Python3_Interpreter_FOUND AND PB_BLENDER_DEFORM)
  add_test(NAME deform_reexport
           COMMAND sh -c "w='${CMAKE_CURRENT_BINARY_DIR}/deform_reexport'; rm -rf \"$w\" && mkdir -p \"$w\" &&
                          PATH=$(echo \"$PATH\" | tr : '\\n' | grep -v pyenv | paste -sd:) \"$0\" -b --factory-startup --python-exit-code 1 -P tests/data/deform/make_deform.py -- --out \"$w\" > \"$w/log\" 2>&1 || { cat \"$w/log\"; exit 1; };
                          for f in deform deform_baked_f00 deform_baked_f12 deform_baked_f24; do
                            \"$1\" tests/gltf_content.py tests/data/deform/$f.gltf \"$w/$f.gltf\" || exit 1; done; echo '4 passed, 0 failed'"
                   ${PB_BLENDER_DEFORM} ${Python3_EXECUTABLE}
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(deform_reexport PROPERTIES LABELS "blender;no-sanitize" TIMEOUT 600
                       PASS_REGULAR_EXPRESSION "4 passed, 0 failed")
endif()

# --frame N poses skins and morph targets in export-pov and reference
# (tests/pose_check.py, against Blender's bake of tests/data/deform).
if(Python3_Interpreter_FOUND)
  add_test(NAME pose_frame_option
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/pose_check.py ${PB_EXE} ${PB_ROOT}
                   ${CMAKE_CURRENT_BINARY_DIR}/pose_frame_option)
  set_tests_properties(pose_frame_option PROPERTIES TIMEOUT 300 PASS_REGULAR_EXPRESSION "9 passed, 0 failed")
endif()
