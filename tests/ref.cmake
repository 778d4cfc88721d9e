# The CPU reference (src/ref), the metrics (src/metrics) and their
# subcommands, reference and compare.

# Slower, tighter versions of two unit tests, too slow for the sanitizer
# build (make test runs that one with -LE no-sanitize).
add_test(NAME test_ref_caustic_full COMMAND test_ref_caustic --full
         WORKING_DIRECTORY ${PB_ROOT})
add_test(NAME test_ref_convergence_full COMMAND test_ref_convergence --full
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(test_ref_caustic_full test_ref_convergence_full
                     PROPERTIES LABELS no-sanitize TIMEOUT 300)

# Exact exit codes from the result table, through sh.
function(pb_ref_cli_test name)
  cmake_parse_arguments(T "" "EXIT;REGEX" "" ${ARGN})
  add_test(NAME ${name}
           COMMAND sh -c "\"$0\" \"$@\"; rc=$?; echo \"exit=$rc\"; [ $rc -eq ${T_EXIT} ]"
                   ${PB_EXE} ${T_UNPARSED_ARGUMENTS}
           WORKING_DIRECTORY ${PB_ROOT})
  if(T_REGEX)
    set_tests_properties(${name} PROPERTIES PASS_REGULAR_EXPRESSION "${T_REGEX}")
  endif()
endfunction()

set(PB_CB ${PB_ROOT}/samples/cornell_box/cornell_box.gltf)
set(PB_REF_OUT ${CMAKE_CURRENT_BINARY_DIR}/ref_out)
file(MAKE_DIRECTORY ${PB_REF_OUT})

pb_ref_cli_test(ref_cli_no_output reference ${PB_CB} EXIT 2
                REGEX "expected SCENE and -o OUT.exr.*exit=2")
pb_ref_cli_test(ref_cli_bad_mode reference ${PB_CB} -o ${PB_REF_OUT}/x.exr --mode bdpt
                EXIT 2 REGEX "unknown value 'bdpt'.*exit=2")
pb_ref_cli_test(ref_cli_bad_alpha reference ${PB_CB} -o ${PB_REF_OUT}/x.exr --photon-alpha 1
                EXIT 2 REGEX "outside.*exit=2")
pb_ref_cli_test(ref_cli_missing_scene reference ${PB_ROOT}/does-not-exist.gltf
                -o ${PB_REF_OUT}/x.exr EXIT 3 REGEX "does-not-exist.gltf.*exit=3")
pb_ref_cli_test(compare_cli_one_file compare ${PB_REF_OUT}/x.exr EXIT 2
                REGEX "expected TEST.exr and REFERENCE.exr.*exit=2")
pb_ref_cli_test(compare_cli_missing compare ${PB_REF_OUT}/nope1.exr ${PB_REF_OUT}/nope2.exr
                EXIT 3 REGEX "nope1.exr.*exit=3")

# reference writes the EXR (with every AOV layer), the PNG and the JSON; the
# image does not depend on the thread count; compare of a file with itself is
# exact; a different seed gives a finite error; sizes and layers that do not
# match are PB_ERR_IMAGE_MISMATCH (exit 9) naming both files.
add_test(NAME ref_cli_cornell_box
         COMMAND sh -c "set -e; exe=\"$0\"; d=\"$1\"; scene=\"$2\"
           \"$exe\" reference \"$scene\" -o \"$d/cb1.exr\" --width 24 --height 24 --spp 4 --threads 1 \\
             --estimate-noise --png \"$d/cb1.png\" --json \"$d/cb1.json\" -q
           \"$exe\" reference \"$scene\" -o \"$d/cb2.exr\" --width 24 --height 24 --spp 4 --threads 2 -q
           \"$exe\" reference \"$scene\" -o \"$d/cb3.exr\" --width 24 --height 24 --spp 4 --seed 9 -q
           \"$exe\" reference \"$scene\" -o \"$d/cb4.exr\" --width 16 --height 24 --spp 1 -q
           test -s \"$d/cb1.png\"
           grep -q '\"guarded_samples\": 0' \"$d/cb1.json\"
           grep -q '\"rmse\"' \"$d/cb1.json\"
           grep -q '\"rays_per_s_per_core\"' \"$d/cb1.json\"
           \"$exe\" compare \"$d/cb2.exr\" \"$d/cb1.exr\" --json \"$d/same.json\" -q
           grep -q '\"rmse\": 0,' \"$d/same.json\"
           grep -q '\"psnr_db\": null' \"$d/same.json\"
           for l in direct indirect albedo normal; do \"$exe\" compare \"$d/cb2.exr\" \"$d/cb1.exr\" --layer $l -q; done
           \"$exe\" compare \"$d/cb3.exr\" \"$d/cb1.exr\" --heatmap \"$d/heat.png\" | grep -q '^SSIM'
           test -s \"$d/heat.png\"
           rc=0; \"$exe\" compare \"$d/cb4.exr\" \"$d/cb1.exr\" 2> \"$d/err.txt\" || rc=$?
           [ $rc -eq 9 ]; grep -q 'cb4.exr is 16x24 but .*cb1.exr is 24x24' \"$d/err.txt\"
           rc=0; \"$exe\" compare \"$d/cb1.exr\" \"$d/cb2.exr\" --layer nosuch 2> \"$d/err.txt\" || rc=$?
           [ $rc -eq 9 ]; grep -q 'neither .*cb1.exr nor .*cb2.exr has layer .nosuch' \"$d/err.txt\"
           \"$exe\" compare \"$d/cb2.exr\" \"$d/cb1.exr\" --layer depth -q
           echo '1 passed, 0 failed'"
           ${PB_EXE} ${PB_REF_OUT} ${PB_CB}
         WORKING_DIRECTORY ${PB_ROOT})

# AUTO picks SPPM for a scene with a mirror and a point light, and photons
# are stored.
add_test(NAME ref_cli_ring_sppm
         COMMAND sh -c "set -e
           \"$0\" reference \"$1/samples/ring/ring.gltf\" -o \"$2/ring.exr\" --width 32 --spp 2 \\
             --json \"$2/ring.json\" -q
           grep -q '\"mode\": \"sppm\"' \"$2/ring.json\"
           ! grep -q '\"stored\": 0,' \"$2/ring.json\"
           echo '1 passed, 0 failed'"
           ${PB_EXE} ${PB_ROOT} ${PB_REF_OUT}
         WORKING_DIRECTORY ${PB_ROOT})

# compare's HDR-FLIP (src/metrics/flip.c): the --heatmap-metric flip map
# and the FLIP keys structurally, a black reference and the error paths'
# codes (tests/flip_heatmap_check.py); and its numbers against NVIDIA FLIP
# 1.7 itself (tests/flip_agreement.py: nine pairs from committed EXRs and
# one CPU reference render, within 0.002 and 2 % of FLIP's mean, the same
# exposures, the same map), which needs tools/flip (scripts/install-deps.sh)
# and FAILS without it.
if(Python3_Interpreter_FOUND)
  add_test(NAME compare_flip_heatmap
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/flip_heatmap_check.py ${PB_EXE}
                   ${CMAKE_CURRENT_BINARY_DIR}/compare_flip_heatmap
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(compare_flip_heatmap PROPERTIES TIMEOUT 120
                       PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed")
  add_test(NAME compare_flip_agreement
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/flip_agreement.py ${PB_EXE}
                   ${CMAKE_CURRENT_BINARY_DIR}/compare_flip_agreement
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(compare_flip_agreement PROPERTIES LABELS "peers;no-sanitize" TIMEOUT 300
                       PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed")
endif()
