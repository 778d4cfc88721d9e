# Texture decoding: test_image_decode (tests/unit) reads the textures that
# tests/fuzz/make_image_seeds.py writes (Pillow; Blender-written ones too
# when Blender is installed), made first by a fixture. Debian's python3
# carries Pillow (python3-pil); another python3 on PATH may not.
if(EXISTS /usr/bin/python3)
  set(PB_SEED_PYTHON /usr/bin/python3)
else()
  set(PB_SEED_PYTHON ${Python3_EXECUTABLE})
endif()
set(PB_IMAGE_SEED_DIR ${CMAKE_CURRENT_BINARY_DIR}/image_seeds)
add_test(NAME image_seeds_make
         COMMAND bash -c "rm -rf \"$1\" && \"$2\" \"$3/tests/fuzz/make_image_seeds.py\" \"$1\" --blender"
                 seeds ${PB_IMAGE_SEED_DIR} ${PB_SEED_PYTHON} ${PB_ROOT})
set_tests_properties(image_seeds_make PROPERTIES FIXTURES_SETUP image_seeds TIMEOUT 300)
set_tests_properties(test_image_decode PROPERTIES FIXTURES_REQUIRED image_seeds
                     ENVIRONMENT PB_IMAGE_SEEDS=${PB_IMAGE_SEED_DIR})
