# Colour management. test_color (the unit-test glob) checks the built-in
# config against the analytic sRGB encode and the published ACEScg matrix,
# and its AgX and Khronos PBR Neutral views against a table of what Blender
# 4.5's own config gives (tests/unit/color_blender4_table.h; with
# $PB_BLENDER4_OCIO naming that config.ocio, against it on 200k colours);
# color_filmic_vs_blender renders a 16-stop ramp EXR through Blender's own
# Filmic view (headless Blender, Image.save_render) and through our shim with
# Blender's config, and compares the PNGs. Skipped (exit 77) without Blender.
add_test(NAME color_filmic_vs_blender COMMAND test_color --blender WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(color_filmic_vs_blender PROPERTIES
  LABELS "blender;no-sanitize" SKIP_RETURN_CODE 77 TIMEOUT 300)

# display subcommand: usage errors and --list.
pb_cli_test(cli_display_no_args display EXIT 2 REGEX "expected IMAGE.exr.*exit=2")
pb_cli_test(cli_display_list display --list --ocio-config built-in EXIT 0
            REGEX "config built-in.*display sRGB: Filmic, AgX, Khronos PBR Neutral, Standard, ACES 1.0 - SDR Video, Raw.*exit=0")
pb_cli_test(cli_display_bad_view display --list --ocio-config built-in --view Nope EXIT 2
            REGEX "config built-in: display 'sRGB' has no view 'Nope'.*exit=2")
# The built-in config has Blender's Filmic and AgX looks (Blender 3.4's and
# 4.5's names and transforms); a look it lacks is still a usage error.
pb_cli_test(cli_display_list_looks display --list --ocio-config built-in EXIT 0
            REGEX "looks: None, Very High Contrast, High Contrast, Medium High Contrast, Medium Contrast, Medium Low Contrast, Low Contrast, Very Low Contrast, AgX - Punchy, AgX - Greyscale, AgX - Very High Contrast, AgX - High Contrast, AgX - Medium High Contrast, AgX - Base Contrast, AgX - Medium Low Contrast, AgX - Low Contrast, AgX - Very Low Contrast\n.*exit=0")
pb_cli_test(cli_display_bad_look display --list --ocio-config built-in --view AgX --look "AgX - Nope" EXIT 2
            REGEX "config built-in: no look 'AgX - Nope' \\(looks: None, Very High Contrast, .*AgX - Punchy, .*exit=2")
# A look through the built-in config: exit 0, no warning, and the picture
# differs from the view's without it.
add_test(NAME cli_display_look_builtin
         COMMAND sh -c "d=$(mktemp -d); in=tests/data/principled2/coat_diffuse/cycles.exr;
                        \"$0\" display $in -o $d/look.png --ocio-config built-in --view AgX --look 'AgX - Punchy' 2>&1; a=$?;
                        \"$0\" display $in -o $d/plain.png --ocio-config built-in --view AgX 2>&1; b=$?;
                        \"$0\" display $in -o $d/filmic.png --ocio-config built-in --view Filmic --look 'High Contrast' 2>&1; c=$?;
                        cmp -s $d/look.png $d/plain.png; same=$?; rm -rf $d;
                        echo \"exit=$a,$b,$c differ=$same\"; [ $a -eq 0 ] && [ $b -eq 0 ] && [ $c -eq 0 ] && [ $same -eq 1 ]"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_display_look_builtin PROPERTIES
  PASS_REGULAR_EXPRESSION "through sRGB / AgX, look AgX - Punchy, [^\n]*OCIO config built-in.*through sRGB / Filmic, look High Contrast, .*exit=0,0,0 differ=1"
  FAIL_REGULAR_EXPRESSION "warning")
# Without --ocio-config, pictures use Blender's own config where Blender is
# installed (this test's machine has it whenever the Blender tests run).
if(EXISTS /usr/share/blender/datafiles/colormanagement/config.ocio)
  pb_cli_test(cli_display_list_blender display --list EXIT 0
              REGEX "config Blender's /usr/share/blender/datafiles/colormanagement/config.ocio.*Filmic.*exit=0")
  # ... and where that config (Blender 3.4's) lacks the view asked for, the
  # built-in one that has it (a 4.x scene's AgX, Khronos PBR Neutral).
  pb_cli_test(cli_display_list_blender_agx display --list --view AgX EXIT 0
              REGEX "config built-in \\(/usr/share/blender/datafiles/colormanagement/config.ocio lacks the display, view or look asked for\\).*AgX.*exit=0")
  pb_cli_test(cli_display_list_blender_agx_missing display --list --view NoSuchView EXIT 2
              REGEX "config Blender's /usr/share/blender/datafiles/colormanagement/config.ocio: display 'sRGB' has no view 'NoSuchView'.*exit=2")
endif()
pb_cli_test(cli_display_missing_config display --list --ocio-config no/such.ocio EXIT 3
            REGEX "no/such.ocio: cannot open.*exit=3")

# A scene's own colour management (the Blender render engine's
# colorManagement) is its PNGs' default view: tests/scene_view.py.
add_test(NAME scene_view COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/scene_view.py ${PB_EXE} ${PB_ROOT}
                                 ${CMAKE_CURRENT_BINARY_DIR}/scene_view)
set_tests_properties(scene_view PROPERTIES LABELS "gpu;no-sanitize" TIMEOUT 300)

# A scene's own OCIO config (colorManagement.ocioConfig, Blender's), its
# fallbacks and their warnings, through `info`: tests/scene_ocio.py.
add_test(NAME color_scene_ocio COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/scene_ocio.py ${PB_EXE} ${PB_ROOT}
                                       ${CMAKE_CURRENT_BINARY_DIR}/scene_ocio)
set_tests_properties(color_scene_ocio PROPERTIES TIMEOUT 120)

# The built-in AgX and Khronos PBR Neutral views, and the AgX looks through
# AgX, against Blender 4.5's own config.ocio (tools/bpy45, installed by
# scripts/install-deps.sh) on 200k colours.
add_test(NAME color_blender45_config COMMAND test_color WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(color_blender45_config PROPERTIES LABELS "blender;blender45;no-sanitize" TIMEOUT 300
  ENVIRONMENT "PB_BLENDER4_OCIO=${PB_ROOT}/tools/bpy45/lib/python3.11/site-packages/bpy/4.5/datafiles/colormanagement/config.ocio")
