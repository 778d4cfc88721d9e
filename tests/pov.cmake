# POV-Ray export.
#   test_pov          (unit-test glob) SDL contents, unit mappings, reports, errors
#   test_pov_render   (unit-test glob) POV-Ray renders vs analytic radiance and a
#                     handedness check; labelled povray;no-sanitize, skips without povray
#   pov_sample_X      every committed sample exports and POV-Ray parses and
#                     renders it (16 px wide, draft quality, no warnings from the parser)
#   cli_export_pov_*  command-line errors
set_tests_properties(test_pov_render PROPERTIES LABELS "povray;no-sanitize" SKIP_RETURN_CODE 77 TIMEOUT 300)

file(GLOB PB_POV_SAMPLES ${PB_ROOT}/samples/*/*.gltf)
foreach(scene ${PB_POV_SAMPLES})
  get_filename_component(sname ${scene} NAME_WE)
  set(work ${CMAKE_CURRENT_BINARY_DIR}/pov_samples/${sname})
  add_test(NAME pov_sample_${sname}
           COMMAND sh -c "command -v povray >/dev/null || { echo 'skip: no povray'; exit 77; }
                          rm -rf '${work}' && mkdir -p '${work}' &&
                          \"$0\" export-pov '${scene}' -o '${work}/${sname}.pov' --width 16 --quality draft &&
                          sh '${PB_ROOT}/validation/run_povray.sh' '${work}/${sname}.pov' '${work}/${sname}.exr' -- -A +WT1 &&
                          test -s '${work}/${sname}.exr' &&
                          if grep -E 'Parse Warning|Possible Parse Error' '${work}/${sname}.exr.log'; then exit 1; fi &&
                          echo '1 passed, 0 failed'"
                  ${PB_EXE}
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(pov_sample_${sname} PROPERTIES LABELS "povray;no-sanitize" SKIP_RETURN_CODE 77
                       TIMEOUT 120 PASS_REGULAR_EXPRESSION "1 passed, 0 failed")
endforeach()

pb_cli_test(cli_export_pov_no_output export-pov samples/cornell_box/cornell_box.gltf EXIT 2
            REGEX "expected SCENE and -o OUT.pov.*exit=2")
pb_cli_test(cli_export_pov_bad_quality export-pov samples/cornell_box/cornell_box.gltf -o x.pov --quality ultra
            EXIT 2 REGEX "unknown value 'ultra'.*exit=2")
pb_cli_test(cli_export_pov_missing export-pov does-not-exist.gltf -o x.pov EXIT 3
            REGEX "does-not-exist.gltf: cannot open.*exit=3")
pb_cli_test(cli_export_pov_bad_camera export-pov samples/cornell_box/cornell_box.gltf -o x.pov --camera Nope EXIT 2
            REGEX "Nope.*exit=2")

# Cycles from the Blender script that builds the sample (validation/run_cycles.sh):
# a tiny render must produce a readable EXR with the sample's aspect. Skips without Blender.
add_test(NAME cycles_smoke_cornell_box
         COMMAND sh -c "command -v blender >/dev/null || { echo 'skip: no blender'; exit 77; }
                        w='${CMAKE_CURRENT_BINARY_DIR}/cycles_smoke' && rm -rf \"$w\" && mkdir -p \"$w\" &&
                        sh '${PB_ROOT}/validation/run_cycles.sh' cornell_box \"$w/cb.exr\" --width 16 --samples 4 --threads 1 &&
                        grep -q '\"width\": 16' \"$w/cb.exr.json\" && grep -q '\"height\": 16' \"$w/cb.exr.json\" &&
                        \"$0\" display \"$w/cb.exr\" -o \"$w/cb.png\" && echo '1 passed, 0 failed'"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cycles_smoke_cornell_box PROPERTIES LABELS "blender;no-sanitize" SKIP_RETURN_CODE 77
                     TIMEOUT 300 PASS_REGULAR_EXPRESSION "1 passed, 0 failed")
