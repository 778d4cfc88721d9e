# Frame sequences through the CLI (tests/sequence_check.py): one test
# per part, so ctest -j runs them side by side. The still and flicker parts
# share a reference cache under the build folder (first run renders it).
foreach(part errors smoke orbit still flicker caustics splat materials deform vsch)
  add_test(NAME sequence_${part}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/sequence_check.py ${PB_EXE} ${PB_ROOT}
                   ${CMAKE_CURRENT_BINARY_DIR}/sequence_${part} ${part})
  set_tests_properties(sequence_${part} PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 900)
endforeach()
