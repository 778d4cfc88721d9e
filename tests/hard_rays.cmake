# Ray-robustness hard cases (tests/unit/hard_rays.h): self-intersection of
# rays spawned with pb_offset_ray and watertightness at vertices and edges.
# test_hard_rays_cpu (Embree, the reference's accel) opens no Vulkan device
# and runs under the sanitizers too; test_hard_rays_gpu (the GPU ray kernel)
# is a GPU test like those of gpu.cmake: validation fatal, skipped (77)
# without a device, kept out of the LeakSanitizer run.
if(TEST test_hard_rays_cpu)
  set_tests_properties(test_hard_rays_cpu PROPERTIES TIMEOUT 600)
endif()
if(TEST test_hard_rays_gpu)
  set_tests_properties(test_hard_rays_gpu PROPERTIES ENVIRONMENT "PB_VK_VALIDATION=1"
                       SKIP_RETURN_CODE 77 LABELS "gpu;no-sanitize" TIMEOUT 600)
endif()
