# The command line: exit codes from the result table, help for every
# subcommand, and `info` on every committed sample.
function(pb_cli_test name)
  cmake_parse_arguments(T "" "EXIT;REGEX;FAIL_REGEX" "" ${ARGN})
  # Run through sh so the exit code can be checked exactly.
  add_test(NAME ${name}
           COMMAND sh -c "\"$0\" \"$@\"; rc=$?; echo \"exit=$rc\"; [ $rc -eq ${T_EXIT} ]"
                   ${PB_EXE} ${T_UNPARSED_ARGUMENTS}
           WORKING_DIRECTORY ${PB_ROOT})
  if(T_REGEX)
    set_tests_properties(${name} PROPERTIES PASS_REGULAR_EXPRESSION "${T_REGEX}")
  endif()
  if(T_FAIL_REGEX)
    set_tests_properties(${name} PROPERTIES FAIL_REGULAR_EXPRESSION "${T_FAIL_REGEX}")
  endif()
endfunction()

pb_cli_test(cli_version --version EXIT 0 REGEX "photonbridge [0-9]+\\.[0-9]+\\.[0-9]+.*exit=0")
pb_cli_test(cli_help help EXIT 0 REGEX "subcommands:.*info.*exit=0")
pb_cli_test(cli_no_args EXIT 2 REGEX "usage: photonbridge SUBCOMMAND.*exit=2")
pb_cli_test(cli_unknown_subcommand frobnicate EXIT 2 REGEX "unknown subcommand 'frobnicate'.*exit=2")
pb_cli_test(cli_info_no_scene info EXIT 2 REGEX "expected one SCENE.*exit=2")
pb_cli_test(cli_info_bad_option info --bogus x.gltf EXIT 2 REGEX "unknown option '--bogus'.*exit=2")
pb_cli_test(cli_info_missing_file info does-not-exist.gltf EXIT 3
            REGEX "does-not-exist.gltf: cannot open.*exit=3")
pb_cli_test(cli_info_bad_units info --light-units kilowatts x.gltf EXIT 2 REGEX "unknown value 'kilowatts'.*exit=2")
pb_cli_test(cli_help_unknown help frobnicate EXIT 2 REGEX "unknown subcommand.*exit=2")
# The command's name once: a message made inside serve ("serve: --socket ...")
# is not prefixed twice ("photonbridge serve: error: serve: ...").
pb_cli_test(cli_error_names_command_once serve --socket ${PB_ROOT}/README.md samples/cornell_box/cornell_box.gltf EXIT 3
            REGEX "photonbridge serve: error: --socket [^\n]*README.md: exists and is not a socket.*exit=3"
            FAIL_REGEX "error: serve:")

# Every subcommand answers --help with its usage and exit 0, and `help X`
# says the same. The list comes from `photonbridge help` itself, so a new
# subcommand is covered without editing this file.
add_test(NAME cli_every_subcommand_help
         COMMAND sh -c "set -e; cmds=$(\"$0\" help | sed -n '/^subcommands:/,$p' | awk 'NR>1{print $1}');
                        [ -n \"$cmds\" ]; n=0;
                        for c in $cmds; do \"$0\" $c --help | grep -q \"usage: photonbridge $c\"; \"$0\" help $c >/dev/null; n=$((n+1)); done;
                        echo \"$n passed, 0 failed\""
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})

# info on every committed sample: loads, has a camera from the file, lights
# and triangles, and no warnings (the samples are our own exports).
file(GLOB PB_SAMPLE_SCENES ${PB_ROOT}/samples/*/*.gltf)
foreach(scene ${PB_SAMPLE_SCENES})
  get_filename_component(sname ${scene} NAME_WE)
  add_test(NAME info_${sname}
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/check_info.py ${PB_EXE} ${scene}
           WORKING_DIRECTORY ${PB_ROOT})
endforeach()

# A misspelt OCIO view fails before any rendering, exit 2, and leaves no output.
add_test(NAME cli_render_bad_view_leaves_nothing
         COMMAND sh -c "d=$(mktemp -d); \"$0\" render samples/cornell_box/cornell_box.gltf -o $d/x.exr --png $d/x.png --view Nope --width 16;
                        rc=$?; n=$(ls $d | wc -l); rm -rf $d; echo \"exit=$rc files=$n\"; [ $rc -eq 2 ] && [ $n -eq 0 ]"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_bad_view_leaves_nothing PROPERTIES PASS_REGULAR_EXPRESSION "no view 'Nope'.*exit=2 files=0")

# --progressive's radius reduction: --alpha outside (0, 1) fails before any
# GPU work (exit 2).
pb_cli_test(cli_render_progressive_bad_alpha render samples/cornell_box/cornell_box.gltf -o x.exr --progressive
            --alpha 1.5 EXIT 2 REGEX "--alpha 1.5 must lie in \\(0, 1\\).*exit=2")

# The normal-map test scene (tests/data/normal_map): the
# loader generates its tangents and the plan compiles normal maps and seed
# 001's eq. 20 correction in.
pb_cli_test(cli_info_normal_map info tests/data/normal_map/normal_map.gltf EXIT 0
            REGEX "\\[normal maps\\].*normal maps on \\(\\+ its correction of the indirect light\\).*exit=0")
pb_cli_test(cli_info_normal_map_json info --json - tests/data/normal_map/normal_map.gltf EXIT 0
            REGEX "\"normal_maps\": *true.*\"shading_normal_correction\": *true.*exit=0")

# An option that takes a value never takes the next option as it: the error
# names the option that lacks its value (exit 2, before any work). "-" and
# negative numbers stay values (--seed -1 reaches the number check).
pb_cli_test(cli_value_not_an_option render samples/cornell_box/cornell_box.gltf -o x.exr --png --width 96 EXIT 2
            REGEX "--png needs a value, got the option '--width'.*exit=2")
pb_cli_test(cli_value_short_option render samples/cornell_box/cornell_box.gltf --camera -o x.exr EXIT 2
            REGEX "--camera needs a value, got the option '-o'.*exit=2")
pb_cli_test(cli_value_negative_number render samples/cornell_box/cornell_box.gltf -o x.exr --seed -1 EXIT 2
            REGEX "--seed: '-1' is not a non-negative integer.*exit=2")

# Every subcommand's --help from outside the checkout: the binary copied to
# a temporary folder and run from / (validate's help is the binary's own,
# with or without the validation scripts).
add_test(NAME cli_help_from_anywhere
         COMMAND sh -c "set -e; d=$(mktemp -d); trap 'rm -rf \"$d\"' EXIT; cp \"$0\" \"$d/pb\"; cd /;
                        cmds=$(\"$d/pb\" help | sed -n '/^subcommands:/,$p' | awk 'NR>1{print $1}'); n=0;
                        for c in $cmds; do \"$d/pb\" $c --help > \"$d/out\"; grep -q \"usage: photonbridge $c\" \"$d/out\"; n=$((n+1)); done;
                        echo \"$n passed, 0 failed\""
                 ${PB_EXE})
set_tests_properties(cli_help_from_anywhere PROPERTIES PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed")

# Cameras that share a name (tests/corpus/valid/duplicate_camera_names: three
# nodes named "Camera" at z = 5, 7, 9): info numbers them, a shared name is
# refused with the numbers, --camera N selects by number.
set(PB_DUP_CAMS tests/corpus/valid/duplicate_camera_names/duplicate_camera_names.gltf)
pb_cli_test(cli_info_camera_numbers info ${PB_DUP_CAMS} EXIT 0
            REGEX "cameras    3\n  0   Camera .*\n  1   Camera .*\n  2   Camera  .*at \\(0 0 9\\).*exit=0")
pb_cli_test(cli_camera_ambiguous_name export-pov ${PB_DUP_CAMS} --camera Camera -o /tmp/pb_never.pov EXIT 2
            REGEX "cameras 0, 1, 2 are all named 'Camera': choose one by its number.*exit=2")
pb_cli_test(cli_camera_number_out_of_range export-pov ${PB_DUP_CAMS} --camera 3 -o /tmp/pb_never.pov EXIT 2
            REGEX "no camera 3 \\(the scene has 3, numbered from 0.*exit=2")
add_test(NAME cli_camera_by_number
         COMMAND sh -c "d=$(mktemp -d); \"$0\" export-pov \"$1\" --camera 2 -o $d/c.pov -q && grep -q 'location <0,0,-9>' $d/c.pov; rc=$?; rm -rf $d; echo \"exit=$rc\"; [ $rc -eq 0 ]"
                 ${PB_EXE} ${PB_DUP_CAMS}
         WORKING_DIRECTORY ${PB_ROOT})
# A file without a camera: info shows the default camera's real aspect (the
# default 640x480 image), not the file's missing one.
pb_cli_test(cli_info_default_camera_aspect info tests/corpus/valid/no_camera/no_camera.gltf EXIT 0
            REGEX "0   default .*aspect 1.333 \\(640x480 by default. the file gives no aspect ratio\\).*exit=0")

# The image-space photon tracer's map count (render --image-maps 1..15): a
# one-line error and exit 2 outside it, before any GPU work.
pb_cli_test(cli_render_image_maps_zero render samples/cornell_box/cornell_box.gltf -o /tmp/pb_never.exr
            --tracer images --image-maps 0 EXIT 2 REGEX "--image-maps: 0 is outside \\[1, 15\\].*exit=2")
pb_cli_test(cli_render_image_maps_99 render samples/cornell_box/cornell_box.gltf -o /tmp/pb_never.exr
            --tracer images --image-maps 99 EXIT 2 REGEX "--image-maps: 99 is outside \\[1, 15\\].*exit=2")
pb_cli_test(cli_render_tracer_unknown render samples/cornell_box/cornell_box.gltf -o /tmp/pb_never.exr
            --tracer kdtree EXIT 2 REGEX "--tracer: unknown value 'kdtree'.*exit=2")
# --tracer wherever a render is configured: view and serve
# take render's choices (the settings table, render/settings.h); the images tracer's options
# without it are an error, not ignored; info lists the tracers.
pb_cli_test(cli_view_tracer_unknown view samples/cornell_box/cornell_box.gltf --tracer kdtree EXIT 2
            REGEX "--tracer: unknown value 'kdtree'.*exit=2")
pb_cli_test(cli_serve_tracer_unknown serve samples/cornell_box/cornell_box.gltf --tracer kdtree EXIT 2
            REGEX "--tracer: unknown value 'kdtree'.*exit=2")
pb_cli_test(cli_serve_image_maps_without_tracer serve samples/cornell_box/cornell_box.gltf --image-maps 4 EXIT 2
            REGEX "serve: error: --image-maps needs --tracer images.*exit=2")
pb_cli_test(cli_view_image_maps_99 view samples/cornell_box/cornell_box.gltf --tracer images --image-maps 99 EXIT 2
            REGEX "--image-maps: 99 is outside \\[1, 15\\].*exit=2")
pb_cli_test(cli_render_image_maps_without_tracer render samples/cornell_box/cornell_box.gltf -o /tmp/pb_never.exr
            --image-map-resolution 64 EXIT 2 REGEX "render: error: --image-map-resolution needs --tracer images.*exit=2")
pb_cli_test(cli_info_tracers info samples/cornell_box/cornell_box.gltf EXIT 0
            REGEX "tracers    bvh \\(default: exact hits in the scene BVH\\), images \\(--image-maps 1..15 cube environment maps.*exit=0")
pb_cli_test(cli_info_tracers_json info --json - samples/cornell_box/cornell_box.gltf EXIT 0
            REGEX "\"tracers\":[ \n\t]*\\[[ \n\t]*\"bvh\",[ \n\t]*\"images\"[ \n\t]*\\].*exit=0")

# The first hour of a new user: a misspelt subcommand, option or value gets
# the closest valid one (within two edits) and the choices; integer bounds
# print as integers; a .blend or a PNG handed to the wrong command is named
# for what it is. Exit codes stay the result table's.
pb_cli_test(cli_subcommand_did_you_mean rendr EXIT 2 REGEX "unknown subcommand 'rendr': did you mean 'render'\\?.*exit=2")
pb_cli_test(cli_option_did_you_mean render samples/cornell_box/cornell_box.gltf -o /tmp/pb_never.exr --widht 64 EXIT 2
            REGEX "unknown option '--widht': did you mean '--width'\\?.*exit=2")
pb_cli_test(cli_option_far_no_guess render samples/cornell_box/cornell_box.gltf -o /tmp/pb_never.exr --frobnicate 64
            EXIT 2 REGEX "unknown option '--frobnicate' \\(see 'render --help'\\).*exit=2" FAIL_REGEX "did you mean")
pb_cli_test(cli_choice_lists_values render samples/cornell_box/cornell_box.gltf -o /tmp/pb_never.exr --estimator foo
            EXIT 2 REGEX "--estimator: unknown value 'foo' \\(one of: lbvh, knn, splat, vsch, auto\\).*exit=2")
pb_cli_test(cli_choice_did_you_mean render samples/cornell_box/cornell_box.gltf -o /tmp/pb_never.exr --first-bounce rms
            EXIT 2 REGEX "--first-bounce: unknown value 'rms': did you mean 'rsm'\\? \\(one of: traced, rsm, auto\\).*exit=2")
pb_cli_test(cli_integer_bound_as_integer render samples/cornell_box/cornell_box.gltf -o /tmp/pb_never.exr --spp 0
            EXIT 2 REGEX "--spp: 0 is outside \\[1, 1048576\\].*exit=2")
add_test(NAME cli_blend_file_named
         COMMAND sh -c "d=$(mktemp -d); printf 'BLENDER-v404REND' > $d/scene.blend;
                        \"$0\" info $d/scene.blend; a=$?; \"$0\" render $d/scene.blend -o $d/x.exr; b=$?;
                        n=$(ls $d | wc -l); rm -rf $d; echo \"exit=$a,$b files=$n\"; [ $a -eq 4 ] && [ $b -eq 4 ] && [ $n -eq 1 ]"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_blend_file_named PROPERTIES
  PASS_REGULAR_EXPRESSION "scene.blend is a Blender file: render it from Blender with the photonbridge add-on, or export glTF.*render: error: [^\n]*scene.blend is a Blender file.*exit=4,4 files=1"
  FAIL_REGULAR_EXPRESSION "not valid JSON")
add_test(NAME cli_display_png_named
         COMMAND sh -c "d=$(mktemp -d); printf '\\211PNG\\r\\n\\032\\n0000IHDR' > $d/in.png;
                        \"$0\" display $d/in.png -o $d/out.png; rc=$?; rm -rf $d; echo \"exit=$rc\"; [ $rc -eq 8 ]"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_display_png_named PROPERTIES
  PASS_REGULAR_EXPRESSION "in.png is a PNG image: this takes a scene-linear OpenEXR \\(.exr\\).*exit=8"
  FAIL_REGULAR_EXPRESSION "magic")

# render -o: the extension says the format. .png is the display-referred
# beauty through the OCIO view (as --png), .exr the multilayer EXR; any
# other is refused (exit 2) before any work, and nothing is written.
add_test(NAME cli_render_output_png
         COMMAND sh -c "d=$(mktemp -d); \"$0\" render samples/cornell_box/cornell_box.gltf -o $d/x.png --width 16 -q --direct-only;
                        rc=$?; magic=$(head -c 4 $d/x.png | od -An -c | tr -d ' '); rm -rf $d; echo \"exit=$rc magic=$magic\"; [ $rc -eq 0 ]"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_output_png PROPERTIES PASS_REGULAR_EXPRESSION "exit=0 magic=[0-9]*PNG")
add_test(NAME cli_render_output_bad_extension
         COMMAND sh -c "d=$(mktemp -d); \"$0\" render samples/cornell_box/cornell_box.gltf -o $d/x.tif --width 16;
                        rc=$?; n=$(ls $d | wc -l); rm -rf $d; echo \"exit=$rc files=$n\"; [ $rc -eq 2 ] && [ $n -eq 0 ]"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_output_bad_extension PROPERTIES
  PASS_REGULAR_EXPRESSION "x.tif: unknown extension '.tif'. accepted: .exr [^\n]* or .png .*exit=2 files=0")
pb_cli_test(cli_export_pov_output_not_pov export-pov samples/cornell_box/cornell_box.gltf -o /tmp/pb_never_cb.exr EXIT 2
            REGEX "-o /tmp/pb_never_cb.exr: the output is POV-Ray scene text and must end in .pov.*exit=2")
pb_cli_test(cli_export_pov_help_says_pov export-pov --help EXIT 0 REGEX "-o, --output OUT +output file \\(.pov\\).*exit=0")

# The device named honestly: its type in render --json, a warning on a CPU
# Vulkan device (not with -q), and the same words on validate's page.
add_test(NAME cli_device_named
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/device_named_check.py ${PB_EXE} ${PB_ROOT}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_device_named PROPERTIES PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed")

# A camera whose clip range excludes every surface (a scene in millimetres
# under a 0.05 m clip start; a clip end in front of the room): render and
# reference say so instead of a silent picture of the world alone.
add_test(NAME cli_camera_clip_empty
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/clip_check.py ${PB_EXE} ${PB_ROOT}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_camera_clip_empty PROPERTIES PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed"
                     LABELS "gpu;no-sanitize" TIMEOUT 600)

# render's progress for a person: a redrawn line on a terminal with the
# stage and the time left, nothing with -q, --progress-lines unchanged.
add_test(NAME cli_render_progress
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/progress_check.py ${PB_EXE} ${PB_ROOT}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_progress PROPERTIES PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed")

# --noise-threshold: refinement to the render's own noise estimate, and that
# estimate within a factor 1.5 of the true error against a converged
# reference (tests/noise_threshold_check.py).
add_test(NAME cli_render_noise_threshold
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/noise_threshold_check.py ${PB_EXE} ${PB_ROOT}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_noise_threshold PROPERTIES PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed"
                     LABELS "gpu;no-sanitize" TIMEOUT 900)

# A method's own signal of failure is said: the environment-map tracer's
# miss rate on sun_atrium (thin columns, a roof: 21 % of segments), and
# splatting on caustics through glass.
add_test(NAME cli_render_warn_image_misses
         COMMAND sh -c "d=$(mktemp -d); \"$0\" render samples/sun_atrium/sun_atrium.gltf --tracer images --width 16 --iterations 1 --photons 16384 -o $d/x.exr 2>&1; rc=$?; rm -rf $d; echo \"exit=$rc\""
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_warn_image_misses PROPERTIES
  PASS_REGULAR_EXPRESSION "warning: render: the environment-map photon tracer \\(--tracer images\\) found no surface for [1-9][0-9] % of its photon segments.*exit=0")
add_test(NAME cli_render_warn_splat_glass
         COMMAND sh -c "d=$(mktemp -d); \"$0\" render samples/cornell_caustics/cornell_caustics.gltf --estimator splat --width 8 --iterations 1 -o $d/x.exr 2>&1; rc=$?; \"$0\" render samples/cornell_box/cornell_box.gltf --estimator splat --width 8 --iterations 1 -o $d/y.exr 2>&1 | grep -c 'biased on caustics'; rm -rf $d; echo \"exit=$rc\""
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_warn_splat_glass PROPERTIES
  PASS_REGULAR_EXPRESSION "warning: render: samples/cornell_caustics/cornell_caustics.gltf: --estimator splat is biased on caustics through glass.*\n0\nexit=0")
set_tests_properties(cli_render_warn_image_misses cli_render_warn_splat_glass PROPERTIES LABELS "gpu;no-sanitize")

# --time-limit with the default one photon map refines with more maps until
# the time is up (the planned count is the option's bound); --progressive
# with one map (--iterations 1) says it does nothing and how to make it work.
add_test(NAME cli_render_time_limit_more_maps
         COMMAND sh -c "d=$(mktemp -d); \"$0\" render samples/cornell_box/cornell_box.gltf -o $d/x.exr --width 8 --photons 256 --time-limit 4 --json - -q; rc=$?; rm -rf $d; echo \"exit=$rc\"; [ $rc -eq 0 ]"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_time_limit_more_maps PROPERTIES
  PASS_REGULAR_EXPRESSION "\"photons\": *\\{[^}]*\"iterations\": *([2-9]|[1-9][0-9]+),.*exit=0")
add_test(NAME cli_render_progressive_one_map
         COMMAND sh -c "d=$(mktemp -d); \"$0\" render samples/cornell_box/cornell_box.gltf -o $d/x.exr --width 8 --photons 1024 --iterations 1 --progressive; rc=$?; rm -rf $d; echo \"exit=$rc\"; [ $rc -eq 0 ]"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_progressive_one_map PROPERTIES
  PASS_REGULAR_EXPRESSION "warning: render: --progressive has no effect with one photon map: add --iterations K \\(K > 1\\) or --time-limit S.*exit=0")
# These five open a Vulkan device: gpu;no-sanitize, as tests/gpu.cmake says
# (lavapipe leaks from a module unloaded before exit, which LeakSanitizer
# cannot name).
set_tests_properties(cli_render_output_png cli_device_named cli_render_progress cli_render_time_limit_more_maps
                     cli_render_progressive_one_map PROPERTIES LABELS "gpu;no-sanitize")
# reference writes EXR only: another extension is refused before any work.
pb_cli_test(cli_reference_output_png reference samples/cornell_box/cornell_box.gltf -o /tmp/pb_never_ref.png EXIT 2
            REGEX "reference: error: -o /tmp/pb_never_ref.png: unknown extension '.png'. accepted: .exr \\(a display-referred PNG: --png FILE.png\\).*exit=2")
pb_cli_test(cli_help_did_you_mean help exprot-pov EXIT 2 REGEX "unknown subcommand 'exprot-pov': did you mean 'export-pov'\\?.*exit=2")

# Help at 80 columns: every subcommand's --help and --help-all, no line
# wider than 80 characters (the widest is printed).
add_test(NAME cli_help_80_columns
         COMMAND sh -c "cmds=$(\"$0\" help | sed -n '/^subcommands:/,$p' | awk 'NR>1{print $1}'); [ -n \"$cmds\" ] || exit 1;
                        n=0; bad=0; for c in $cmds; do for h in --help --help-all; do
                          w=$(\"$0\" $c $h | awk '{ if (length($0) > m) m = length($0) } END { print m + 0 }');
                          echo \"$c $h: $w columns\"; n=$((n+1)); [ \"$w\" -le 80 ] || bad=$((bad+1)); done; done;
                        echo \"$((n-bad)) passed, $bad failed\""
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_help_80_columns PROPERTIES PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed")

# The advanced switches (algorithm choices, benchmarks, ablations) under
# --help-all only; --help says they are there.
add_test(NAME cli_help_all_advanced
         COMMAND sh -c "set -e; h=$(\"$0\" render --help); a=$(\"$0\" render --help-all);
                        for o in --estimator --leaf-size --no-edge-correction --splat-ntile --first-bounce --progress-lines; do
                          if echo \"$h\" | grep -q -- \"$o\"; then echo \"$o in --help\"; exit 1; fi;
                          echo \"$a\" | grep -q -- \"$o\" || { echo \"$o not in --help-all\"; exit 1; }; done;
                        for o in --spp --photons --png --width --view --device --time-limit; do
                          echo \"$h\" | grep -q -- \"$o\" || { echo \"$o not in --help\"; exit 1; }; done;
                        echo \"$h\" | grep -q -- '--help-all  *also the [0-9]* advanced options';
                        echo \"$h\" | grep -q '^Sampling:$'; echo \"$h\" | grep -q '^Photons:$'; echo \"$h\" | grep -q '^Colour:$';
                        echo ok-advanced"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_help_all_advanced PROPERTIES PASS_REGULAR_EXPRESSION "ok-advanced")

# Help speaks of the product: no paper section or equation numbers and no
# tracker numbers in any subcommand's --help-all.
add_test(NAME cli_help_no_references
         COMMAND sh -c "cmds=$(\"$0\" help | sed -n '/^subcommands:/,$p' | awk 'NR>1{print $1}'); [ -n \"$cmds\" ] || exit 1;
                        for c in $cmds; do \"$0\" $c --help-all; done > /dev/null || exit 1;
                        for c in $cmds; do \"$0\" $c --help-all | grep -n -i -E 'seed 0|seed [0-9]{3}|eq\\. ?[0-9]|issue *#?[0-9]' | sed \"s/^/$c: /\"; done | tee /dev/stderr | grep -q . && exit 1;
                        echo ok-no-references"
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_help_no_references PROPERTIES PASS_REGULAR_EXPRESSION "ok-no-references")

# validate's help in the style of the rest (not the Python script's), and
# -o like every other subcommand (--out, its former name, still works).
pb_cli_test(cli_validate_help_style validate --help EXIT 0
            REGEX "usage: photonbridge validate SCENE -o DIR.*\nOutput:\n  -o, --output DIR .*exit=0" FAIL_REGEX "validate.py|usage: validate")
pb_cli_test(cli_validate_dash_o validate does-not-exist.gltf -o x EXIT 2 REGEX "does-not-exist.gltf: no such scene.*exit=2")
pb_cli_test(cli_validate_typo validate cornell_box -o x --ref-sp 4 EXIT 2
            REGEX "unknown option '--ref-sp': did you mean '--ref-spp'\\?.*exit=2")

# Lights in the units the artist typed: Blender's watts (and a sun's W/m^2)
# for a scene the add-on wrote, beside the radiometric value rendered; glTF's
# candela for a plain KHR_lights_punctual light, the whole line exact.
pb_cli_test(cli_info_blender_watts info samples/blender/metal_plastic/handoff/metal_plastic.gltf EXIT 0
            REGEX "\n  Key +directional strength 2.5 W/m\\^2 in Blender \\(E = 2.5 W/m\\^2\\) [^\n]*\n  Fill +point +120 W in Blender \\(I = 9.549 W/sr\\) x colour \\(1 0.85 0.7\\), [^\n]*emits 102 W.*exit=0")
# The writer's KHR_materials_clearcoat / _sheen (the plain glTF of a Principled
# v2 coat and sheen, as Blender's exporter writes them) are read through the
# material's PHOTONBRIDGE_blender model: no "is ignored" warning.
pb_cli_test(cli_info_blender_coat_no_warning info tests/data/principled2/coat/coat.gltf EXIT 0
            REGEX "\nwarnings +0\n.*exit=0")
pb_cli_test(cli_info_blender_sheen_no_warning info tests/data/principled2/sheen/sheen.gltf EXIT 0
            REGEX "\nwarnings +0\n.*exit=0")
pb_cli_test(cli_info_gltf_candela info samples/cornell_box/cornell_box.gltf EXIT 0
            REGEX "\n  CeilingLight         point       8153 cd in glTF \\(I = 11.94 W/sr\\) x colour \\(1 1 1\\), at \\(0 1.75 0\\), emits 150 W\n.*exit=0")
# Blender 4.x's light Exposure is in the file's power already (2^exposure);
# info shows the watts typed and the exposure: 120 W written at +1 is 60 W.
add_test(NAME cli_info_blender_exposure
         COMMAND sh -c "set -e; d=$(mktemp -d); trap 'rm -rf \"$d\"' EXIT; cp samples/blender/metal_plastic/handoff/* \"$d\";
                        \"$1\" -c \"import json,sys; p=sys.argv[1]; g=json.load(open(p)); [n['extensions']['PHOTONBRIDGE_blender']['light'].update(exposure=1.0) for n in g['nodes'] if n.get('name') == 'Fill']; json.dump(g, open(p, 'w'))\" \"$d/metal_plastic.gltf\";
                        \"$0\" info \"$d/metal_plastic.gltf\""
                 ${PB_EXE} ${Python3_EXECUTABLE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_info_blender_exposure PROPERTIES
                     PASS_REGULAR_EXPRESSION "\n  Fill +point +60 W at exposure \\+1 in Blender \\(I = 9.549 W/sr\\)")
# validate checks its options in C before the script runs: every option of
# validation/validate.py is in its --help-all (--out as -o/--output's old name).
add_test(NAME cli_validate_options_in_step
         COMMAND sh -c "\"$0\" validate --help-all | \"$1\" -c \"import re,sys; names = re.findall(r'add_argument\\\\(\\\"(--[a-z0-9-]+)\\\"', open('validation/validate.py').read()); h = sys.stdin.read(); missing = [n for n in names if not re.search('(^|[ ,])' + re.escape(n) + '([ =]|$)', h, re.M)]; print(len(names), 'options; missing from validate --help-all:', missing or 'none'); sys.exit(1 if missing or not names else 0)\""
                 ${PB_EXE} ${Python3_EXECUTABLE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_validate_options_in_step PROPERTIES PASS_REGULAR_EXPRESSION "missing from validate --help-all: none")

# The settings table (render/settings.h) once: the add-on's copy
# (exporters/blender/photonbridge/settings_table.py) is what the binary
# writes (`make settings-table` rewrites it); `settings` lists every row;
# render, view and serve offer the same options with the same ranges.
add_test(NAME cli_settings_table_current
         COMMAND sh -c "\"$0\" settings --python | diff -u \"$1\" - && echo same"
                 ${PB_EXE} ${CMAKE_SOURCE_DIR}/exporters/blender/photonbridge/settings_table.py)
set_tests_properties(cli_settings_table_current PROPERTIES PASS_REGULAR_EXPRESSION "^same")
add_test(NAME cli_settings_everywhere
         COMMAND python3 ${CMAKE_SOURCE_DIR}/tests/settings_check.py ${PB_EXE}
                 ${CMAKE_SOURCE_DIR}/exporters/blender/photonbridge/settings_table.py)
set_tests_properties(cli_settings_everywhere PROPERTIES PASS_REGULAR_EXPRESSION "[1-9][0-9]* passed, 0 failed")
