# The add-on's panels, Device menu and defaults (tests/blender/bl_ui.py):
# photonbridge's own Render Properties panels register for the engine and
# draw without error, the Device menu lists what a fake binary reports and
# reaches the CLI as --device N, and every setting's default is the one
# `photonbridge render --help-all` states. In the Debian Blender (3.4) and in
# Blender 4.5 LTS (the bpy module in tools/bpy45; missing, a failure).
add_test(NAME blender_ui
         COMMAND sh -c "command -v \"\${BLENDER:-blender}\" >/dev/null || { echo 'skip: no blender'; exit 77; }; exec \"\${BLENDER:-blender}\" -b --factory-startup --python-exit-code 1 --python \"$0/tests/blender/bl_ui.py\" -- \"$0\" \"$1\" \"$2\""
                 ${PB_ROOT} ${PB_EXE} ${CMAKE_CURRENT_BINARY_DIR}/blender_ui)
set_tests_properties(blender_ui PROPERTIES SKIP_RETURN_CODE 77 LABELS "blender;no-sanitize" TIMEOUT 300)
add_test(NAME blender45_ui
         COMMAND ${PB_ROOT}/tools/bpy45/bin/python ${PB_ROOT}/tests/blender/bl_ui.py ${PB_ROOT} ${PB_EXE}
                 ${CMAKE_CURRENT_BINARY_DIR}/blender45_ui)
set_tests_properties(blender45_ui PROPERTIES LABELS "blender;blender45;no-sanitize" TIMEOUT 300)

# The same panels drawn by Blender 3.4 itself, with its window under
# xvfb-run (tests/blender/bl_ui_window.py): Blender calls every panel's draw
# and none raises. Skips (77) without Blender or xvfb-run.
add_test(NAME blender_ui_window
         COMMAND sh -c "command -v blender >/dev/null && command -v xvfb-run >/dev/null || { echo 'skip: needs blender and xvfb-run'; exit 77; }; exec xvfb-run -a -s '-screen 0 1280x1500x24' blender --factory-startup \"$0/samples/cornell_box/cornell_box.blend\" --python \"$0/tests/blender/bl_ui_window.py\" -- \"$0\" \"$1\" \"$2\""
                 ${PB_ROOT} ${PB_EXE} ${CMAKE_CURRENT_BINARY_DIR}/blender_ui_window)
set_tests_properties(blender_ui_window PROPERTIES SKIP_RETURN_CODE 77 LABELS "blender;no-sanitize" TIMEOUT 300
                     RESOURCE_LOCK xvfb)
