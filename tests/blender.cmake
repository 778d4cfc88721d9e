# The Blender render engine (exporters/blender/photonbridge) headless in the
# Debian Blender (tests/blender/blender_check.py): one test per part. Each
# skips with a clear line (exit 77) where Blender, a Vulkan device or (for
# the validator) npm's gltf-validator is missing.
foreach(part register install writer instances validator f12 cancel animation vcolor groups mix mapping lightnodes floattex unsupported badinput sky cameras everyday)
  add_test(NAME blender_${part}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/blender/blender_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/blender_${part} ${part})
  set_tests_properties(blender_${part} PROPERTIES SKIP_RETURN_CODE 77 LABELS "blender;no-sanitize" TIMEOUT 900)
endforeach()

# The same checks in Blender 4.5 LTS: the bpy module that scripts/install-deps.sh
# installs into tools/bpy45, driven through tests/blender/bpy_blender.py (the
# `blender` command line over the module). Missing bpy is a failure, not a
# skip: the set-up installs it on every machine.
set(PB_BPY45 ${PB_ROOT}/tools/bpy45/bin/python)
foreach(part register install writer lights45 cancel badinput)
  add_test(NAME blender45_${part}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/blender/blender_check.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/blender45_${part} ${part})
  set_tests_properties(blender45_${part} PROPERTIES SKIP_RETURN_CODE 77 LABELS "blender;blender45;no-sanitize"
                       TIMEOUT 900 ENVIRONMENT "PB_BLENDER_PYTHON=${PB_BPY45}")
endforeach()

# Texture colour spaces in the add-on's image writer (tests/blender/bl_colorspace.py):
# in the Debian Blender (3.4), and in Blender 4.5 (tools/bpy45, above).
add_test(NAME blender_colorspace
         COMMAND sh -c "command -v \"\${BLENDER:-blender}\" >/dev/null || { echo 'skip: no blender'; exit 77; }; exec \"\${BLENDER:-blender}\" -b --factory-startup --python-exit-code 1 --python \"$0/tests/blender/bl_colorspace.py\" -- \"$0\" \"$1\""
                 ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/blender_colorspace)
set_tests_properties(blender_colorspace PROPERTIES SKIP_RETURN_CODE 77 LABELS "blender;no-sanitize" TIMEOUT 300)
add_test(NAME blender45_colorspace
         COMMAND ${PB_BPY45} ${PB_ROOT}/tests/blender/bl_colorspace.py ${PB_ROOT} ${CMAKE_CURRENT_BINARY_DIR}/blender45_colorspace)
set_tests_properties(blender45_colorspace PROPERTIES LABELS "blender;blender45;no-sanitize" TIMEOUT 300)
