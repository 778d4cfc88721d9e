# The Blender materials against Cycles 3.4 (tests/principled_lobes.py): each
# Principled lobe alone, a rough glass and the white furnace, rendered by the
# reference and by the GPU pipeline and compared with the committed Cycles
# renders of tests/data/principled (exporters/blender/make_principled_tests.py):
# mean within 1 %, PSNR >= 35 dB. The GPU run has the Vulkan validation
# layers (fatal) on four renders whose passes and specializations cover the
# rest: the studio (progressive photon maps, full global illumination) both
# ways, the rough glass (transmission, an emitter) and the furnace (emission
# alone); the others render without the layers (principled_lobes.py
# --validate).
if(Python3_Interpreter_FOUND)
  add_test(NAME principled_lobes_ref
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/principled_lobes.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/principled_ref --renderer ref
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(principled_lobes_ref PROPERTIES TIMEOUT 600 LABELS principled
                       PASS_REGULAR_EXPRESSION " 0 failed")
  add_test(NAME principled_lobes_gpu
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/principled_lobes.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/principled_gpu --renderer gpu
                   --validate studio --validate studio@R1 --validate glass --validate furnace
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(principled_lobes_gpu PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       TIMEOUT 1200 LABELS "gpu;no-sanitize;principled" PASS_REGULAR_EXPRESSION " 0 failed")
endif()
# The studio benchmark's driver end to end in its smoke mode (one tiny point
# per renderer and scene: every option it passes exists, every output it
# reads is written).
if(Python3_Interpreter_FOUND)
  add_test(NAME bench_principled_smoke
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/bench/principled_studio.py --smoke --exe ${PB_EXE}
                   --probe $<TARGET_FILE:exr_probe> --out ${CMAKE_CURRENT_BINARY_DIR}/bench_principled_smoke
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(bench_principled_smoke PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600
                       LABELS "gpu;no-sanitize;bench;principled" PASS_REGULAR_EXPRESSION "principled_studio: 8 points")
endif()
add_test(NAME cli_render_glossy_path_roughness_over
         COMMAND sh -c "\"$0\" render tests/data/principled/studio/studio.gltf -o x.exr --glossy-path-roughness 1.5; echo \"exit=$?\""
                 ${PB_EXE}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(cli_render_glossy_path_roughness_over PROPERTIES
                     PASS_REGULAR_EXPRESSION "glossy-path-roughness: 1.5 is outside \\[0, 1\\].*exit=2")
# The render engine's writer on every Principled test scene, rebuilt in
# Blender: the same material extension as the committed glTF whose Cycles
# render principled_lobes compares with, loaded as the same Blender model
# (tests/blender/principled_writer.py).
add_test(NAME principled_writer
         COMMAND sh -c "command -v blender >/dev/null || { echo 'skip: no blender'; exit 77; }
                        PATH=$(echo \"$PATH\" | tr : '\\n' | grep -v pyenv | paste -sd:) blender -b --factory-startup \
                          --python-exit-code 1 -P tests/blender/principled_writer.py -- \"$0\" \"$1\""
                 ${PB_EXE} ${CMAKE_CURRENT_BINARY_DIR}/principled_writer
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(principled_writer PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600
                     LABELS "blender;no-sanitize;principled" PASS_REGULAR_EXPRESSION "26 passed, 0 failed")
# Principled v2 (Blender 4.x): the render engine's writer on v2 materials in
# Blender 4.x run as a Python module (PB_BPY4_PYTHON, a venv with bpy 4.x;
# tests/blender/principled2_writer.py): the extension's principled2 model
# against the sockets, the plain glTF against Blender's own exporter, and
# the loader.
set(PB_BPY4_PYTHON "${PB_ROOT}/tools/bpy45/bin/python" CACHE FILEPATH "Python with bpy 4.x (Blender as a module)")
add_test(NAME principled2_writer
         COMMAND sh -c "[ -x \"$0\" ] || { echo 'FAIL Blender 4.5 (bpy) missing: run scripts/install-deps.sh'; exit 1; }; \"$0\" tests/blender/principled2_writer.py \"$1\" \"$2\""
                 ${PB_BPY4_PYTHON} ${PB_EXE} ${CMAKE_CURRENT_BINARY_DIR}/principled2_writer
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(principled2_writer PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 600
                     LABELS "blender;no-sanitize;principled" PASS_REGULAR_EXPRESSION " 0 failed")
# The reference's Principled v2 closure stack against Cycles 4.5's renders of
# tests/data/principled2 (exporters/blender/make_principled2_tests.py): each
# lobe alone and the thin film (on the specular, over a diffuse base, on
# glass), >= 40 dB and the mean within 0.5 %.
if(Python3_Interpreter_FOUND)
  add_test(NAME principled2_lobes_ref
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/principled_lobes.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/principled2_ref --renderer ref --data tests/data/principled2
                   --psnr 40 --mean-tol 0.005
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(principled2_lobes_ref PROPERTIES TIMEOUT 900 LABELS principled
                       PASS_REGULAR_EXPRESSION " 0 failed")
endif()
# The GPU's Principled v2 (shaders/common/principled.glsl, its own code)
# against the same Cycles 4.5 renders: >= 36 dB, mean within 1 %. The
# validation layers (fatal) on four renders: the normal map (a texture),
# the rough glass (transmission, an emitter), the coated emission and the
# anisotropic F82 metal with every glossy layer followed by the eye path.
if(Python3_Interpreter_FOUND)
  add_test(NAME principled2_lobes_gpu
           COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/principled_lobes.py ${PB_EXE} $<TARGET_FILE:exr_probe>
                   ${CMAKE_CURRENT_BINARY_DIR}/principled2_gpu --renderer gpu --data tests/data/principled2
                   --psnr 36 --mean-tol 0.01 --validate normal_half --validate glass_ggx
                   --validate emission_coat --validate metallic_f82_multi_aniso@R1
                   --validate mix_principled_metallic_mask
           WORKING_DIRECTORY ${PB_ROOT})
  set_tests_properties(principled2_lobes_gpu PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1" SKIP_RETURN_CODE 77
                       TIMEOUT 1800 LABELS "gpu;no-sanitize;principled" PASS_REGULAR_EXPRESSION " 0 failed")
endif()
# A bad value in the Metallic BSDF's model: one line naming the file, the
# material and the member.
add_test(NAME principled2_metallic_bad_value
         COMMAND sh -c "mkdir -p \"$1\" && cp tests/data/principled2/metallic_f82_ggx/metallic_f82_ggx.bin \"$1\"/ &&
                        sed 's/\"fresnelType\": \"F82\"/\"fresnelType\": \"SCHLICK\"/' \
                          tests/data/principled2/metallic_f82_ggx/metallic_f82_ggx.gltf > \"$1\"/bad.gltf &&
                        \"$0\" info \"$1\"/bad.gltf; echo \"exit=$?\""
                 ${PB_EXE} ${CMAKE_CURRENT_BINARY_DIR}/principled2_metallic_bad
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(principled2_metallic_bad_value PROPERTIES LABELS principled
                     PASS_REGULAR_EXPRESSION "bad\\.gltf: materials\\[0\\]\\.extensions\\.PHOTONBRIDGE_blender\\.metallic\\.fresnelType: 'SCHLICK' is not F82 or PHYSICAL_CONDUCTOR\n.*exit=[1-9]")
# The Glossy and Refraction BSDFs' models: an Anisotropy past -1..1 and a
# Multiscatter Refraction (Blender has none) are one line naming the member.
add_test(NAME principled2_bsdf_node_bad_value
         COMMAND sh -c "mkdir -p \"$1\" && cd \"$1\" && d=\"$2\"/tests/data/principled2 &&
                        cp $d/glossy_ggx_negative/glossy_ggx_negative.bin $d/refraction_bsdf/refraction_bsdf.bin . &&
                        sed 's/\"anisotropy\": -0.5/\"anisotropy\": -1.5/' $d/glossy_ggx_negative/glossy_ggx_negative.gltf > glossy.gltf &&
                        sed 's/\"distribution\": \"GGX\"/\"distribution\": \"MULTI_GGX\"/' $d/refraction_bsdf/refraction_bsdf.gltf > refraction.gltf &&
                        \"$0\" info glossy.gltf; echo \"exit=$?\"; \"$0\" info refraction.gltf; echo \"exit=$?\""
                 ${PB_EXE} ${CMAKE_CURRENT_BINARY_DIR}/principled2_bsdf_node_bad ${PB_ROOT}
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(principled2_bsdf_node_bad_value PROPERTIES LABELS principled
                     PASS_REGULAR_EXPRESSION "glossy\\.gltf: materials\\[0\\]\\.extensions\\.PHOTONBRIDGE_blender\\.glossy\\.anisotropy: -1\\.5[^\n]*\n.*exit=[1-9].*refraction\\.gltf: materials\\[[0-9]\\]\\.extensions\\.PHOTONBRIDGE_blender\\.refraction\\.distribution: 'MULTI_GGX' is not GGX or BECKMANN\n.*exit=[1-9]")
# A Mix Shader of two BSDFs (the extension's "mix"): the written scene loads
# without a warning and compiles the mix; broken variants are one line
# naming the member, exit 5; two shaders of one closure kind warn.
add_test(NAME principled2_mix_shader_cli
         COMMAND ${Python3_EXECUTABLE} ${PB_ROOT}/tests/mix_shader_cli.py ${PB_EXE} ${CMAKE_CURRENT_BINARY_DIR}/mix_shader_cli
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(principled2_mix_shader_cli PROPERTIES LABELS principled PASS_REGULAR_EXPRESSION "\n0 failed\n")
# The writer on Mix Shaders in Blender 4.5 (tests/blender/mix_writer.py):
# which mixes become the extension's "mix", which fall back with a warning.
add_test(NAME principled2_mix_writer
         COMMAND sh -c "[ -x \"$0\" ] || { echo 'FAIL Blender 4.5 (bpy) missing: run scripts/install-deps.sh'; exit 1; }; \"$0\" tests/blender/mix_writer.py \"$1\" \"$2\""
                 ${PB_BPY4_PYTHON} ${PB_EXE} ${CMAKE_CURRENT_BINARY_DIR}/mix_writer
         WORKING_DIRECTORY ${PB_ROOT})
set_tests_properties(principled2_mix_writer PROPERTIES TIMEOUT 600 LABELS "blender;no-sanitize;principled"
                     PASS_REGULAR_EXPRESSION "13 passed, 0 failed")
