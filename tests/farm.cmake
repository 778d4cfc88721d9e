# Render farms (tests/farm/): --warmup and per-frame seeds for
# chunked shots, the Flamenco 3 job type compiled in node against a stub of
# the manager's globals, and a shot on a one-node Slurm cluster the test
# starts and stops itself (root, unshare -n). Each skips (77, one line)
# where node, slurm-wlm or network namespaces are missing.
foreach(part seeds chunks)
  set(parts ${part})
  if(part STREQUAL "seeds")
    set(parts errors seeds)
  endif()
  add_test(NAME farm_${part}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/farm/chunks_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/farm_${part} ${parts})
  set_tests_properties(farm_${part} PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 300)
endforeach()

find_program(PB_NODE NAMES node nodejs)
if(PB_NODE)
  add_test(NAME farm_flamenco COMMAND ${PB_NODE} ${PB_ROOT}/tests/farm/flamenco_jobtype.js ${PB_ROOT})
else()
  add_test(NAME farm_flamenco COMMAND ${CMAKE_COMMAND} -E echo "skip: node not installed (scripts/install-deps.sh installs nodejs)")
  set_tests_properties(farm_flamenco PROPERTIES SKIP_REGULAR_EXPRESSION "skip: node")
endif()
set_tests_properties(farm_flamenco PROPERTIES TIMEOUT 60)

add_test(NAME farm_slurm
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/farm/slurm_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/farm_slurm)
set_tests_properties(farm_slurm PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 300 RUN_SERIAL TRUE)
add_test(NAME farm_slurm_validate
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/farm/slurm_validate_check.py ${PB_EXE} ${PB_ROOT}
                 ${CMAKE_CURRENT_BINARY_DIR}/farm_slurm_validate)
set_tests_properties(farm_slurm_validate PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 300
                     RUN_SERIAL TRUE)
