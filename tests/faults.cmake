# Fault injection: tests/faults.sh CASE runs photonbridge
# under one fault each (no Vulkan driver, a device without a needed feature,
# a GPU memory cap, an unwritable output folder, a full disk, SIGINT/SIGTERM)
# and asserts the exit code, a one-line error and an unchanged output folder.
# Cases that open a Vulkan device run with validation layers (any message is
# then exit 13, which fails the expected code) and the gpu;no-sanitize labels;
# they skip (77) without a device.
find_program(PB_BASH bash)
if(PB_BASH)
  foreach(c unwritable_cpu disk_full_cpu interrupt_cpu no_device)
    add_test(NAME faults_${c} COMMAND ${PB_BASH} ${PB_ROOT}/tests/faults.sh ${c} ${PB_EXE}
             WORKING_DIRECTORY ${PB_ROOT})
    set_tests_properties(faults_${c} PROPERTIES PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed"
                         FAIL_REGULAR_EXPRESSION "FAIL:" TIMEOUT 300 LABELS faults)
  endforeach()
  # no_device opens no device, but the validate run in it starts the reference
  # renderer and python: no-sanitize keeps the ASan pass short.
  set_tests_properties(faults_no_device PROPERTIES LABELS "faults;no-sanitize")
  foreach(c no_feature memory_cap unwritable_gpu disk_full_gpu interrupt_gpu)
    add_test(NAME faults_${c} COMMAND ${PB_BASH} ${PB_ROOT}/tests/faults.sh ${c} ${PB_EXE}
             WORKING_DIRECTORY ${PB_ROOT})
    set_tests_properties(faults_${c} PROPERTIES PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed"
                         FAIL_REGULAR_EXPRESSION "FAIL:" TIMEOUT 600 SKIP_RETURN_CODE 77
                         ENVIRONMENT "PB_VK_VALIDATION=1" LABELS "faults;gpu;no-sanitize")
  endforeach()
endif()

# Valgrind memcheck over the CPU paths (tests/valgrind.sh):
# info and export-pov on every sample, the reference at 16x16 (path tracing,
# SPPM, textures), compare/display and their error paths, a dozen broken
# corpus files. Memory errors and definite/indirect/possible leaks fail;
# suppressions (tests/valgrind.supp) are third-party only. About 80 s in all
# on the 2-core CI machine. Not under ASan (valgrind cannot run its binaries).
if(PB_BASH)
  foreach(g info render_cpu images export_pov corpus)
    add_test(NAME valgrind_${g} COMMAND ${PB_BASH} ${PB_ROOT}/tests/valgrind.sh ${g} ${PB_EXE}
             WORKING_DIRECTORY ${PB_ROOT})
    set_tests_properties(valgrind_${g} PROPERTIES LABELS "valgrind;no-sanitize" SKIP_RETURN_CODE 77 TIMEOUT 600
                         PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed" FAIL_REGULAR_EXPRESSION "FAIL:")
  endforeach()
endif()
