# The render options of programs that drive photonbridge (the Blender add-on;
# tests/render_drive.py): crops, Blender's channel names, progress lines,
# previews and the time limit, and their errors. One test per part.
foreach(part errors crop blender progress)
  add_test(NAME render_drive_${part}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/render_drive.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/render_drive_${part} ${part})
  set_tests_properties(render_drive_${part} PROPERTIES SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 600)
endforeach()
