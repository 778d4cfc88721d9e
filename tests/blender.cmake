# The Blender render engine (exporters/blender/photonbridge) headless in the
# Debian Blender (tests/blender/blender_check.py): one test per part. Each
# skips with a clear line (exit 77) where Blender, a Vulkan device or (for
# the validator) npm's gltf-validator is missing.
foreach(part register writer instances validator f12 cancel animation vcolor groups mix mapping lightnodes floattex unsupported badinput sky cameras everyday)
  add_test(NAME blender_${part}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/blender/blender_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/blender_${part} ${part})
  set_tests_properties(blender_${part} PROPERTIES SKIP_RETURN_CODE 77 LABELS "blender;no-sanitize" TIMEOUT 900)
endforeach()

# Texture colour spaces in the add-on's image writer (tests/blender/bl_colorspace.py):
# in the Debian Blender (3.4), and in a Blender 4.x bpy module's Python where
# $PB_BPY_PYTHON names it (e.g. a venv with `pip install bpy==4.5.*`).
add_test(NAME blender_colorspace
         COMMAND sh -c "command -v \"\${BLENDER:-blender}\" >/dev/null || { echo 'skip: no blender'; exit 77; }; exec \"\${BLENDER:-blender}\" -b --factory-startup --python-exit-code 1 --python \"$0/tests/blender/bl_colorspace.py\" -- \"$0\" \"$1\""
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/blender_colorspace)
set_tests_properties(blender_colorspace PROPERTIES SKIP_RETURN_CODE 77 LABELS "blender;no-sanitize" TIMEOUT 300)
add_test(NAME blender4_colorspace
         COMMAND sh -c "[ -n \"$PB_BPY_PYTHON\" ] || { echo 'skip: $PB_BPY_PYTHON (a Blender 4.x bpy Python) not set'; exit 77; }; \"$PB_BPY_PYTHON\" \"$0/tests/blender/bl_colorspace.py\" \"$0\" \"$1\""
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/blender4_colorspace)
set_tests_properties(blender4_colorspace PROPERTIES SKIP_RETURN_CODE 77 LABELS "blender;no-sanitize" TIMEOUT 300)
