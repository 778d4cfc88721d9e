# Compiles shaders/*/*.comp to SPIR-V with glslc at build time and embeds each
# as a C array header, ${CMAKE_BINARY_DIR}/generated/shaders/NAME.spv.h,
# defining `static const uint32_t pb_spv_NAME[]`. glslc writes a depfile
# (-MD), so editing an included header (shaders/shared/*.h,
# shaders/common/*.glsl) recompiles exactly the shaders that include it; the
# explicit DEPENDS on those folders is a second guard for generators without
# depfile support. Defines the target pb_shaders (pb depends on it).
#
# PB_SHADERS_FROM: another build tree of this source whose modules this tree
# uses (make test's ASan tree takes the normal tree's): the SPIR-V does not
# depend on the C compiler's flags, so it is compiled once. This tree's
# pb_shaders builds them there and pb includes them from there.
set(PB_SHADERS_FROM "" CACHE PATH "a build tree of this source whose compiled shaders this tree uses (empty: its own)")
if(PB_SHADERS_FROM)
  if(NOT EXISTS ${PB_SHADERS_FROM}/CMakeCache.txt)
    message(FATAL_ERROR "PB_SHADERS_FROM: ${PB_SHADERS_FROM} is not a configured build tree of photonbridge")
  endif()
  # No modules of this tree's own to shadow the other tree's.
  file(REMOVE_RECURSE ${CMAKE_BINARY_DIR}/generated/shaders)
  # MAKEFLAGS cleared: the outer make's jobserver does not reach this child.
  add_custom_target(pb_shaders COMMAND ${CMAKE_COMMAND} -E env MAKEFLAGS= ${CMAKE_COMMAND} --build ${PB_SHADERS_FROM}
                                       --target pb_shaders
                    COMMENT "shaders: compiled in ${PB_SHADERS_FROM}" VERBATIM)
  target_include_directories(pb PUBLIC ${PB_SHADERS_FROM}/generated)
  return()
endif()
find_program(GLSLC glslc REQUIRED)
# One folder per concern (frame, scene, photon, estimate, filter); a
# kernel's name is its file's name, unique across the folders.
file(GLOB PB_SHADER_SOURCES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/shaders/*/*.comp)
file(GLOB PB_SHADER_HEADERS CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/shaders/shared/*.h
     ${CMAKE_SOURCE_DIR}/shaders/common/*.glsl)
set(PB_SHADER_OUT ${CMAKE_BINARY_DIR}/generated/shaders)
file(MAKE_DIRECTORY ${PB_SHADER_OUT})
set(PB_SHADER_OUTPUTS "")

# One module: SRC compiled with the defines that follow (glslc, depfile) into
# NAME.spv and embedded as pb_spv_NAME in NAME.spv.h.
# The SPIR-V as a C array (shaders/spv_embed.c, a build-time tool).
add_executable(pb_spv_embed ${CMAKE_SOURCE_DIR}/shaders/spv_embed.c)

function(pb_shader name src)
  set(spv ${PB_SHADER_OUT}/${name}.spv)
  set(hdr ${PB_SHADER_OUT}/${name}.spv.h)
  add_custom_command(
    OUTPUT ${spv}
    COMMAND ${GLSLC} --target-env=vulkan1.1 -O -g -DPB_GLSL=1 ${ARGN}
            -I ${CMAKE_SOURCE_DIR}/shaders -MD -MF ${spv}.d -o ${spv} ${src}
    DEPENDS ${src} ${PB_SHADER_HEADERS}
    DEPFILE ${spv}.d
    COMMENT "glslc ${name}"
    VERBATIM)
  add_custom_command(
    OUTPUT ${hdr}
    COMMAND pb_spv_embed ${spv} ${hdr} ${name}
    DEPENDS ${spv} pb_spv_embed
    COMMENT "embed ${name}.spv"
    VERBATIM)
  set(PB_SHADER_OUTPUTS ${PB_SHADER_OUTPUTS} ${hdr} PARENT_SCOPE)
endfunction()

foreach(src ${PB_SHADER_SOURCES})
  get_filename_component(name ${src} NAME_WE)
  if(DEFINED PB_SHADER_SRC_${name})
    message(FATAL_ERROR "two shaders named ${name}: ${PB_SHADER_SRC_${name}} and ${src}")
  endif()
  set(PB_SHADER_SRC_${name} ${src})
  pb_shader(${name} ${src})
endforeach()

# The passes that shade surfaces are built twice: as above, without the
# Blender materials (their code is not in the module: glTF scenes compile
# exactly what they did before), and with -DPB_BLENDER=1 as NAME_blender
# (pb_spv_NAME_blender), which the passes load for scenes with Blender
# materials (plan.h blender_materials).
set(PB_SHADER_BLENDER_VARIANTS gbuffer direct gather knn photon_trace photon_rsm splat_resolve vsch_shade)
foreach(name ${PB_SHADER_BLENDER_VARIANTS})
  pb_shader(${name}_blender ${PB_SHADER_SRC_${name}} -DPB_BLENDER=1)
endforeach()
# The image-space photon tracer (seed 003; src/render/photon/tracer_images.c):
# photon_trace.comp with -DPB_IMAGE_TRACER=1, whose segments are searched in
# the environment maps (common/image_maps.glsl) instead of the BVH, as
# photon_trace_images and photon_trace_images_blender.
pb_shader(photon_trace_images ${PB_SHADER_SRC_photon_trace} -DPB_IMAGE_TRACER=1)
pb_shader(photon_trace_images_blender ${PB_SHADER_SRC_photon_trace} -DPB_IMAGE_TRACER=1
          -DPB_BLENDER=1)
# The multi-level up-sampling's gather (seed 003 sec. 6; src/render/estimate/upsample.c):
# gather.comp with -DPB_UPSAMPLE=1, the diffuse irradiance at a list of pixels
# and the rest at full resolution, as gather_upsample and
# gather_upsample_blender.
pb_shader(gather_upsample ${PB_SHADER_SRC_gather} -DPB_UPSAMPLE=1)
pb_shader(gather_upsample_blender ${PB_SHADER_SRC_gather} -DPB_UPSAMPLE=1 -DPB_BLENDER=1)
# raycast_rq.comp (GLSL 460, VK_KHR_ray_query) is compiled by the glob as it
# is; only devices created with the ray-query extensions
# (pb_gpu_limits.ray_query) load it.
# The ray-query builds of every kernel that casts rays (common/bvh.glsl
# pb_trace through rayQueryEXT, the scene's acceleration structure at the
# BVH nodes' binding): NAME_rq, and NAME_rq_blender for the passes with a
# Blender build. GL_EXT_ray_query needs GLSL 460: -std=460 raises the
# sources' #version 450 for these builds only (-w: glslc warns that it did),
# so the modules every device loads stay as they were.
set(PB_SHADER_RAY_QUERY_VARIANTS gbuffer direct gather knn photon_trace photon_rsm vsch_shade vsch_leaf image_maps
    motion)
foreach(name ${PB_SHADER_RAY_QUERY_VARIANTS})
  pb_shader(${name}_rq ${PB_SHADER_SRC_${name}} -std=460 -w -DPB_RAY_QUERY=1)
  if(name IN_LIST PB_SHADER_BLENDER_VARIANTS)
    pb_shader(${name}_rq_blender ${PB_SHADER_SRC_${name}} -std=460 -w -DPB_RAY_QUERY=1 -DPB_BLENDER=1)
  endif()
endforeach()
pb_shader(gather_upsample_rq ${PB_SHADER_SRC_gather} -std=460 -w -DPB_RAY_QUERY=1 -DPB_UPSAMPLE=1)
pb_shader(gather_upsample_rq_blender ${PB_SHADER_SRC_gather} -std=460 -w -DPB_RAY_QUERY=1
          -DPB_UPSAMPLE=1 -DPB_BLENDER=1)
add_custom_target(pb_shaders DEPENDS ${PB_SHADER_OUTPUTS})
