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
