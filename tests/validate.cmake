# Cross-renderer validation (issue 7, parts 4 and 5).
#   validate_report_chromium  `photonbridge validate cornell_box` at 48 px (reference, GPU
#                             render, POV-Ray draft, Cycles when installed), then the
#                             report page in headless Chromium: the screenshot must not
#                             be blank (validation/png_check.py: luma std >= 10, >= 16
#                             colours) and report.json must hold every pair's metrics.
#                             Labelled chromium;no-sanitize; skips (77) without chromium.
#   test_validate_calib       (unit-test glob) reference vs POV-Ray, direct light only,
#                             thresholds in the file; labelled povray;no-sanitize.
#   cycles_calib              validation/cycles_calib_check.py: the watt convention of
#                             shared/VALIDATION.md against Blender's Cycles (point, spot,
#                             sun on a Lambertian plane, direct light, 1 %), with the
#                             reference rendering the glTF Blender exported from the same
#                             scenes. Labelled blender;no-sanitize; skips without Blender.
#   cli_validate_*            command-line errors.
add_test(NAME validate_report_chromium
         COMMAND sh -c "c=$(command -v chromium || command -v chromium-browser) || { echo 'skip: no chromium'; exit 77; }
                        w='${CMAKE_CURRENT_BINARY_DIR}/validate_report' && rm -rf \"$w\" && mkdir -p \"$w\" &&
                        \"$0\" validate cornell_box --out \"$w/cb\" --width 48 --spp 2 --ref-spp 8 --pov-quality draft \
                          --cycles-spp 8 --threads 1 &&
                        test -s \"$w/cb/index.html\" && test -s \"$w/cb/report.json\" &&
                        python3 -c \"import json,sys; r=json.load(open(sys.argv[1])); ok=[x['name'] for x in r['renders'] if x['status']=='ok']; n=len(ok); assert len(r['pairs'])==n*(n-1)//2, r['pairs']; assert all('psnr_db' in p and 'relmse' in p and p.get('heatmap') for p in r['pairs']), r['pairs']; assert r['versions']['photonbridge']; print('renders ok:', ok)\" \"$w/cb/report.json\" &&
                        u=$(mktemp -d) &&
                        timeout 120 \"$c\" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
                          --disable-background-networking --disable-component-update --disable-sync \
                          --user-data-dir=\"$u\" --screenshot=\"$w/shot.png\" --window-size=1200,900 \
                          \"file://$w/cb/index.html\" >\"$w/chromium.log\" 2>&1;
                        rm -rf \"$u\";
                        test -s \"$w/shot.png\" || { echo 'no screenshot'; cat \"$w/chromium.log\"; exit 1; } &&
                        python3 '${PB_ROOT}/validation/png_check.py' \"$w/shot.png\" &&
                        echo '1 passed, 0 failed'"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(validate_report_chromium PROPERTIES LABELS "chromium;no-sanitize" SKIP_RETURN_CODE 77
                     TIMEOUT 600 PASS_REGULAR_EXPRESSION "1 passed, 0 failed")

# png_check itself: a uniform picture is blank, a gradient is not.
add_test(NAME validate_png_check_selftest COMMAND python3 ${PB_ROOT}/validation/png_check.py --selftest)
set_tests_properties(validate_png_check_selftest PROPERTIES PASS_REGULAR_EXPRESSION "1 passed, 0 failed" TIMEOUT 60)

pb_cli_test(cli_validate_no_out validate cornell_box EXIT 2 REGEX "required: --out.*exit=2")
pb_cli_test(cli_validate_missing validate does-not-exist.gltf --out x EXIT 2
            REGEX "does-not-exist.gltf: no such scene.*exit=2")

# Calibration against POV-Ray (tests/unit/test_validate_calib.c; thresholds there).
set_tests_properties(test_validate_calib PROPERTIES LABELS "povray;calibration;no-sanitize"
                     SKIP_RETURN_CODE 77 TIMEOUT 600)
add_test(NAME test_validate_calib_gi COMMAND test_validate_calib --gi WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(test_validate_calib_gi PROPERTIES LABELS "povray;calibration;no-sanitize"
                     SKIP_RETURN_CODE 77 TIMEOUT 600)
# cornell_box, direct light only, 1 % mean relative error over smooth regions. It failed at
# 11 % while the reference (and the GPU, which shares its BSDF) gave Blender's
# "Specular 0" materials a grazing Fresnel layer (F0 = 0, F90 = 1) that darkened the
# diffuse at grazing view; the loader now drops a layer with zero F0 whole (scene.h), and
# the agreement is 0.22 % (64x64, 64 spp, POV-Ray direct preset).
add_test(NAME test_validate_calib_cornell_direct COMMAND test_validate_calib --cornell-direct
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(test_validate_calib_cornell_direct PROPERTIES LABELS "povray;calibration;no-sanitize"
                     SKIP_RETURN_CODE 77 TIMEOUT 600)

# The watt convention against Cycles (validation/cycles_calib_check.py; thresholds there).
add_test(NAME cycles_calib
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/validation/cycles_calib_check.py ${PB_EXE}
                 $<TARGET_FILE:exr_probe> ${CMAKE_CURRENT_BINARY_DIR}/cycles_calib --threads 1
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cycles_calib PROPERTIES LABELS "blender;calibration;no-sanitize" SKIP_RETURN_CODE 77
                     TIMEOUT 600)
