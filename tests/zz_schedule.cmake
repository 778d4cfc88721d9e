# The order ctest -j starts the tests in on a clean checkout (no
# Testing/Temporary/CTestCostData.txt yet, as in CI): the longest first, so
# that none of them starts last and runs alone at the end. COST is each
# test's seconds on a quiet 2-core machine (lavapipe, 2026-12-07); once a
# run has measured them, ctest's own figures take over.
# (Included last: the tests/*.cmake modules are read in name order.)
set(PB_TEST_COSTS
  principled2_lobes_gpu 384
  gpu_traversal_same_pictures 315
  principled_lobes_gpu 257
  blender_everyday 161
  blender45_samples_gpu 140
  hard_cases_gpu_vsch_directional 134
  hard_cases_gpu_vsch 133
  blender_f12 131
  hard_cases_gpu_knn 114
  gpu_cli_render_tracer_images_samples 108
  blender_viewport 98
  test_gpu_soft_lights 84
  blender_floattex 75
  cli_render_noise_threshold 65
  blender_cameras 65
  valgrind_info 64
  hard_cases_gpu 61
  test_gpu_vsch 59
  blender_sky 58
  blender45_badinput 55
  blender_badinput 54
  blender_samples_gpu 51
  cycles_gltf_samples 45
  estimator_samples 44
  bench_principled_smoke 42
  blender_animation 41
  hard_cases_gpu_splat 40
)
list(LENGTH PB_TEST_COSTS n)
math(EXPR last "${n} - 1")
foreach(i RANGE 0 ${last} 2)
  math(EXPR j "${i} + 1")
  list(GET PB_TEST_COSTS ${i} name)
  list(GET PB_TEST_COSTS ${j} cost)
  if(TEST ${name})
    set_tests_properties(${name} PROPERTIES COST ${cost})
  endif()
endforeach()
