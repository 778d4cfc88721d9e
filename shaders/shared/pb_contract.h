/* The shader contract, written once: the descriptor binding of every storage
 * buffer of every kernel (set 0) and the specialization-constant ids, as
 * plain #defines that C and GLSL (#include "shared/pb_contract.h") both
 * read. A kernel declares `layout(binding = PB_..._BIND_...)`, the host
 * fills its binding array with the same names; tests/unit/test_gpu_contract.c
 * reads the Binding and SpecId decorations of every embedded SPIR-V module
 * and checks them against these values (as test_gpu_layout checks the
 * struct layouts of pb_gpu.h).
 *
 * A pipeline's bindings are 0 .. COUNT-1 (pb_gpu_pipeline_desc.binding_count
 * = the kernel's PB_..._BIND_COUNT); a binding a kernel does not declare is
 * still bound (any buffer will do). Numbers never change meaning: a kernel
 * that needs a new buffer takes a new number. */
#ifndef PB_CONTRACT_H
#define PB_CONTRACT_H

/* ---- the scene passes (common/scene.glsl): gbuffer.comp, direct.comp; the
 * photon tracer, the RSM pass and the gather share 0-10, 13, 14 ---------- */
#define PB_BIND_FRAME 0         /* pb_gpu_frame */
#define PB_BIND_NODES 1         /* BVH nodes; the TLAS in the ray-query builds */
#define PB_BIND_TRIS 2          /* BVH triangles */
#define PB_BIND_INDICES 3
#define PB_BIND_NORMALS 4
#define PB_BIND_UVS 5
#define PB_BIND_TRI_MATERIAL 6
#define PB_BIND_MATERIALS 7
#define PB_BIND_TEXTURES 8
#define PB_BIND_TEXELS 9
#define PB_BIND_LIGHTS 10
#define PB_BIND_GBUFFER 11      /* pb_gpu_gbuffer[] (the passes' own I/O) */
#define PB_BIND_ACCUM 12        /* pb_gpu_accum[] */
#define PB_BIND_POSITIONS 13
#define PB_BIND_EMITTERS 14
#define PB_BIND_WORLD 15        /* pb_gpu_world + data (common/lights.glsl) */
#define PB_BIND_COUNT 16

/* ---- gather.comp: the scene's 0-14 (11, 12 as above), then ---------------- */
#define PB_GATHER_BIND_PHOTONS 15 /* sorted photons, as uvec4 */
#define PB_GATHER_BIND_NODES 16   /* LBVH nodes, as uvec4 */
#define PB_GATHER_BIND_INFO 17    /* pb_gpu_lbvh_info */
#define PB_GATHER_BIND_ACCUM 18   /* pb_gpu_photon_accum[] */
#define PB_GATHER_BIND_NMAP 19    /* pb_gpu_photon_nmap[] (normal maps only) */
#define PB_GATHER_BIND_COUNT 20
/* gather_upsample (gather.comp with -DPB_UPSAMPLE=1): the gather's 0-19, then */
#define PB_GATHER_BIND_UPS_IRR 20  /* vec4 per pixel: irradiance (shared/pb_upsample.h) */
#define PB_GATHER_BIND_UPS_LIST 21 /* uint: header, pixel indices */
#define PB_GATHER_UPS_BIND_COUNT 22

/* ---- upsample_mark.comp, upsample_compose.comp (seed 003 sec. 6, Figure 9;
 * shared/pb_upsample.h): the scene's 0-14 (11 the G-buffer, 12 the
 * accumulators), then ------------------------------------------------------ */
#define PB_UPS_BIND_IRR 15      /* vec4 per pixel: irradiance, state */
#define PB_UPS_BIND_LIST 16     /* uint: header, pixel indices */
#define PB_UPS_BIND_PACCUM 17   /* pb_gpu_photon_accum[] (compose) */
#define PB_UPS_BIND_COUNT 18

/* ---- knn.comp (estimator_knn.c): the gather's 15-19, the same buffers ----- */
#define PB_KNN_BIND_PHOTONS PB_GATHER_BIND_PHOTONS /* the LBVH's sorted photons */
#define PB_KNN_BIND_NODES PB_GATHER_BIND_NODES     /* its nodes */
#define PB_KNN_BIND_INFO PB_GATHER_BIND_INFO       /* pb_gpu_lbvh_info */
#define PB_KNN_BIND_ACCUM PB_GATHER_BIND_ACCUM     /* pb_gpu_photon_accum[] */
#define PB_KNN_BIND_NMAP PB_GATHER_BIND_NMAP       /* pb_gpu_photon_nmap[] */
#define PB_KNN_BIND_COUNT 20 /* the gather's count without gather_upsample's */

/* ---- splat_count.comp, splat_splat.comp, splat_resolve.comp (seed 001
 * 24.3; shared/pb_splat.h): the scene's 0-14 (the resolve shades with them;
 * count and splat read the frame at 0 and the G-buffer at 11), then ------- */
#define PB_SPLAT_BIND_PHOTONS 15  /* pb_gpu_photon[] of the map */
#define PB_SPLAT_BIND_COUNTS 16   /* pb_gpu_photon_counts of the map */
#define PB_SPLAT_BIND_TILES 17    /* uint n_p per screen tile (atomics) */
#define PB_SPLAT_BIND_TARGET 18   /* PB_SPLAT_PIXEL_WORDS uints per pixel */
#define PB_SPLAT_BIND_ACCUM 19    /* pb_gpu_photon_accum[] (resolve) */
#define PB_SPLAT_BIND_NMAP 20     /* pb_gpu_photon_nmap[] (normal maps only) */
#define PB_SPLAT_BIND_STATS 21    /* pb_gpu_splat_stats (atomics) */
#define PB_SPLAT_BIND_COUNT 22

/* ---- the view-sample cluster hierarchy (seed 004; shared/pb_vsch.h) ------
 * vsch_clear, _range, _mark, _scan, _cone, _up, _count, _fill, _ranges: */
#define PB_VSCH_BIND_FRAME 0      /* pb_gpu_frame (as the scene's 0) */
#define PB_VSCH_BIND_GBUFFER 1    /* pb_gpu_gbuffer[] */
#define PB_VSCH_BIND_DATA 2       /* uint[]: header, nodes, pixels, photons */
#define PB_VSCH_BIND_PHOTONS 3    /* the map's pb_gpu_photon[] */
#define PB_VSCH_BIND_COUNTS 4     /* the map's pb_gpu_photon_counts */
#define PB_VSCH_BIND_KEYS 5       /* the sort's keys (node ids) */
#define PB_VSCH_BIND_VALS 6       /* the sort's values (photon ids) */
#define PB_VSCH_BIND_COUNT 7
/* vsch_leaf, _shade, _blur: the scene's 0-14 (11, 12 as in gather.comp), then */
#define PB_VSCH_SHADE_BIND_DATA 15
#define PB_VSCH_SHADE_BIND_PHOTONS 16
#define PB_VSCH_SHADE_BIND_VALS 17
#define PB_VSCH_SHADE_BIND_ACCUM 18 /* pb_gpu_photon_accum[] */
#define PB_VSCH_SHADE_BIND_NMAP 19  /* pb_gpu_photon_nmap[] (normal maps only) */
#define PB_VSCH_SHADE_BIND_COUNT 20

/* ---- photon_trace.comp: the scene's 0-10, 13, 14, then -------------------- */
#define PB_PHOTON_BIND_PHOTONS 11    /* pb_gpu_photon[] */
#define PB_PHOTON_BIND_COUNTS 12     /* pb_gpu_photon_counts */
#define PB_PHOTON_BIND_PARAMS 15     /* pb_gpu_photon_params + lights */
#define PB_PHOTON_BIND_RSM_LIGHTS 16 /* pb_gpu_rsm_light[] */
#define PB_PHOTON_BIND_RSM_TEXELS 17 /* pb_gpu_rsm_texel[] */
#define PB_PHOTON_BIND_WORLD 18
#define PB_PHOTON_BIND_COUNT 19

/* ---- photon_trace_images (photon_trace.comp built with -DPB_IMAGE_TRACER:
 * the image-space tracer of seed 003): photon_trace.comp's 0-18, then ---- */
#define PB_PHOTON_BIND_IMAGE_MAPS 19   /* pb_gpu_image_maps_info + pb_gpu_image_map[] */
#define PB_PHOTON_BIND_IMAGE_TEXELS 20 /* pb_gpu_image_texel[] */
#define PB_PHOTON_BIND_IMAGE_COUNTS 21 /* pb_gpu_image_counts */
#define PB_PHOTON_IMAGES_BIND_COUNT 22

/* ---- image_maps.comp (renders the maps) and image_maps_query.comp (rays
 * against the maps: tests, benchmark); shared/pb_image_maps.h ------------- */
#define PB_IMAGE_BIND_NODES 0       /* BVH nodes (image_maps.comp); its ray-query build: the TLAS */
#define PB_IMAGE_BIND_TRIS 1        /* BVH triangles (image_maps.comp) */
#define PB_IMAGE_BIND_INDICES 2
#define PB_IMAGE_BIND_POSITIONS 3
#define PB_IMAGE_BIND_TRI_MATERIAL 4
#define PB_IMAGE_BIND_MAPS 5        /* pb_gpu_image_maps_info + pb_gpu_image_map[] */
#define PB_IMAGE_BIND_TEXELS 6      /* pb_gpu_image_texel[] */
#define PB_IMAGE_BIND_RAYS 7        /* query: pb_gpu_ray[] */
#define PB_IMAGE_BIND_HITS 8        /* query: pb_gpu_hit[] (u: the outcome) */
#define PB_IMAGE_BIND_COUNTS 9      /* query: pb_gpu_image_counts; touch: pb_gpu_image_touch */
#define PB_IMAGE_BIND_COUNT 10

/* ---- photon_rsm.comp: the scene's 0-10, 13, 14, then ---------------------- */
#define PB_RSM_BIND_LIGHTS 11
#define PB_RSM_BIND_TEXELS 12
#define PB_RSM_BIND_COUNT 15

/* ---- the LBVH build (common/lbvh.glsl: lbvh_setup, _bounds, _morton, _climb) */
#define PB_LBVH_BIND_INFO 0
#define PB_LBVH_BIND_PHOTONS_IN 1
#define PB_LBVH_BIND_MAP_COUNTS 2
#define PB_LBVH_BIND_SORTED 3
#define PB_LBVH_BIND_KEYS 4
#define PB_LBVH_BIND_VALS 5
#define PB_LBVH_BIND_NODES 6
#define PB_LBVH_BIND_VISIT 7
#define PB_LBVH_BIND_PARTIAL 8
#define PB_LBVH_BIND_PHOTONS_IN4 9  /* binding 1 again, as uvec4 */
#define PB_LBVH_BIND_SORTED4 10     /* binding 3 again, as uvec4 */
#define PB_LBVH_BIND_NODES4 11      /* binding 6 again, as uvec4 */
#define PB_LBVH_BIND_COUNT 12

/* ---- the radix sort (common/lbvh_sort.glsl: lbvh_sort_*) ------------------ */
#define PB_SORT_BIND_STATE 0
#define PB_SORT_BIND_KEYS 1
#define PB_SORT_BIND_VALS 2
#define PB_SORT_BIND_HIST 3
#define PB_SORT_BIND_COUNT_SRC 4
#define PB_SORT_BIND_KEYS4 5        /* binding 1 again, as uvec4 */
#define PB_SORT_BIND_VALS4 6        /* binding 2 again, as uvec4 */
#define PB_SORT_BIND_COUNT 7

/* ---- atrous.comp ----------------------------------------------------------- */
#define PB_ATROUS_BIND_S 0
#define PB_ATROUS_BIND_DETAIL 1
#define PB_ATROUS_BIND_GEO 2
#define PB_ATROUS_BIND_INDIRECT 3
#define PB_ATROUS_BIND_ALBEDO 4
#define PB_ATROUS_BIND_COUNT 5

/* ---- temporal.comp --------------------------------------------------------- */
#define PB_TEMPORAL_BIND_HIST_IN 0
#define PB_TEMPORAL_BIND_GEO_PREV 1
#define PB_TEMPORAL_BIND_GEO 2
#define PB_TEMPORAL_BIND_INDIRECT 3
#define PB_TEMPORAL_BIND_ALBEDO 4
#define PB_TEMPORAL_BIND_MOTION 5
#define PB_TEMPORAL_BIND_HIST_OUT 6
#define PB_TEMPORAL_BIND_RESULT 7   /* vec4: filtered radiance (remodulated), history length L */
#define PB_TEMPORAL_BIND_STATS 8    /* pb_gpu_temporal_stats (atomics) */
#define PB_TEMPORAL_BIND_COUNT 9

/* ---- filter_io.comp (src/render/filter/filters.c): the filters' inputs packed from
 * the resolved planes, their outputs composed back into them ---------------- */
#define PB_FILTER_IO_BIND_PLANES 0        /* the resolve's float planes */
#define PB_FILTER_IO_BIND_PHOTON_PLANES 1 /* the resolve's photon planes */
#define PB_FILTER_IO_BIND_GEO 2           /* vec4: edge-stopping normal, depth */
#define PB_FILTER_IO_BIND_ALBEDO 3        /* vec4: albedo (demodulation) */
#define PB_FILTER_IO_BIND_INDIRECT_IN 4   /* vec4: indirect to filter, w = L (1) */
#define PB_FILTER_IO_BIND_INDIRECT 5      /* vec4: the filtered indirect */
#define PB_FILTER_IO_BIND_CAUSTIC_IN 6    /* vec4: caustics to filter */
#define PB_FILTER_IO_BIND_CAUSTIC 7       /* vec4: the filtered caustics */
#define PB_FILTER_IO_BIND_GUARD 8         /* uint: non-finite values replaced */
#define PB_FILTER_IO_BIND_COUNT 9

/* ---- shading_correction.comp (eq. 20 on the resolved planes) --------------- */
#define PB_SHADING_BIND_PLANES 0
#define PB_SHADING_BIND_PHOTON_PLANES 1
#define PB_SHADING_BIND_COUNT 2

/* ---- motion.comp ----------------------------------------------------------- */
#define PB_MOTION_BIND_NODES 0      /* BVH nodes; the ray-query build: the TLAS */
#define PB_MOTION_BIND_TRIS 1
#define PB_MOTION_BIND_INDICES 2
#define PB_MOTION_BIND_PREV_POSITIONS 3
#define PB_MOTION_BIND_PARAMS 4
#define PB_MOTION_BIND_MOTION 5
#define PB_MOTION_BIND_COUNT 6

/* ---- raycast.comp ---------------------------------------------------------- */
#define PB_RAYCAST_BIND_NODES 0
#define PB_RAYCAST_BIND_TRIS 1
#define PB_RAYCAST_BIND_RAYS 2
#define PB_RAYCAST_BIND_HITS 3
#define PB_RAYCAST_BIND_COUNT 4

/* ---- ray_query/raycast_rq.comp (devices with VK_KHR_ray_query) ----------- */
#define PB_RAYCAST_RQ_BIND_TLAS 0  /* accelerationStructureEXT (src/gpu/accel.c) */
#define PB_RAYCAST_RQ_BIND_RAYS 1
#define PB_RAYCAST_RQ_BIND_HITS 2
#define PB_RAYCAST_RQ_BIND_COUNT 3

/* ---- resolve.comp (shared/pb_resolve.h) ---------------------------------- */
#define PB_RESOLVE_BIND_ACCUM 0         /* pb_gpu_accum[] */
#define PB_RESOLVE_BIND_PHOTON_ACCUM 1  /* pb_gpu_photon_accum[] (photons on) */
#define PB_RESOLVE_BIND_NMAP 2          /* pb_gpu_photon_nmap[] (normal maps) */
#define PB_RESOLVE_BIND_OUT 3           /* float planes */
#define PB_RESOLVE_BIND_GUARD 4         /* uint: non-finite values replaced */
#define PB_RESOLVE_BIND_OUT_PHOTONS 5   /* float planes of the photon AOVs */
#define PB_RESOLVE_BIND_KPD_SUMS 6      /* pb_gpu_resolve_kpd: k_PD's two sums over the frame */
#define PB_RESOLVE_BIND_COUNT 7

/* ---- present.comp (shared/pb_present.h): the viewer's picture -------------- */
#define PB_PRESENT_BIND_LUT 0   /* vec4 nodes of the baked view (color.h pb_color_lut) */
#define PB_PRESENT_BIND_IN 1    /* float: the AOV (the resolved beauty, RGBA) */
#define PB_PRESENT_BIND_OUT 2   /* uint: RGBA8 (R in the low byte), the displayed image */
#define PB_PRESENT_BIND_COUNT 3

/* ---- accumulate.comp (shared/pb_accumulate.h): a still run's running means */
#define PB_ACCUM_BIND_PLANES 0         /* the resolve's float planes (beauty, direct) */
#define PB_ACCUM_BIND_PHOTON_PLANES 1  /* the photon planes (indirect, caustic) */
#define PB_ACCUM_BIND_SUM 2            /* float: the running means, PB_ACCUM_FLOATS a pixel */
#define PB_ACCUM_BIND_COUNT 3

/* ---- specialization constants (constant_id) ------------------------------- */
/* The scene's (common/scene.glsl), set by the passes from the render plan
 * (render/scene/scene_plan.h). Ids 0-5 are every shading pass's (PB_SPEC_SHADING_COUNT); the
 * others belong to the kernels that name them. */
#define PB_SPEC_HAS_NORMALS 0
#define PB_SPEC_TEXTURES 1
#define PB_SPEC_SPECULAR 2        /* delta lobes: eye chains */
#define PB_SPEC_EMISSIVE 3        /* emissive triangles or unlit surfaces */
#define PB_SPEC_PRINCIPLED2 4     /* Principled v2 materials (PB_BLENDER builds
                                     only): the v2 stack compiled out of the
                                     scenes without one */
#define PB_SPEC_CLOSURES 5        /* PB_CLOSURES_* (PB_BLENDER builds only):
                                     the closures the scene's Blender
                                     materials can make; the others' code is
                                     compiled out */
#define PB_SPEC_TRANSMISSION 6    /* photon_trace.comp only */
#define PB_SPEC_NORMAL_MAPS 7     /* gather.comp only (eq. 20's sums) */
#define PB_SPEC_SOFT_LIGHTS 8
#define PB_SPEC_WORLD 9
#define PB_SPEC_ALPHA 10          /* PB_BLENDER builds only */
#define PB_SPEC_COUNT 11
/* Every pass that shades a surface takes the scene's ids up to this one
 * (0-5) from the frame's set. */
#define PB_SPEC_SHADING_COUNT (PB_SPEC_CLOSURES + 1)
/* knn.comp's own, after the scene's: k, the size of each query's max-heap. */
#define PB_SPEC_KNN_K 11
#define PB_SPEC_KNN_BUDGET 12 /* loop iterations per query; 0: no bound */
#define PB_SPEC_KNN_COUNT 13

/* PB_SPEC_CLOSURES: bit k is closure slot k of common/bsdf.glsl
 * (PB_SLOT_*; the transparent slot is always compiled), then the code paths
 * a slot's closure may take. A bit the scene's materials cannot need
 * leaves that code out of the module (lavapipe: the direct pass of a
 * Principled BSDF without sheen, glass or coat compiles in a third of the
 * time); the host sets a bit wherever a material might need it
 * (scene.c pb_blender_closures), textures counted as reaching any value. */
#define PB_CLOSURES_DIFFUSE 0x01u
#define PB_CLOSURES_SHEEN 0x02u
#define PB_CLOSURES_SPECULAR 0x04u
#define PB_CLOSURES_GLASS_REFL 0x08u /* "reflection": glass, the v2 metal, the Glossy BSDF */
#define PB_CLOSURES_GLASS_REFR 0x10u /* "refraction" */
#define PB_CLOSURES_CLEARCOAT 0x20u
#define PB_CLOSURES_MULTI_WALK 0x40u /* v1 Multiscatter GGX's random walk */
#define PB_CLOSURES_V1 0x80u         /* the v1 Principled BSDF's set-up */
#define PB_CLOSURES_MIX 0x100u       /* a Mix Shader of two shaders (pb_gpu_material.mix_with) */
#define PB_CLOSURES_ALL 0x1ffu

/* lbvh_climb.comp's own. */
#define PB_SPEC_FENCES 0
#define PB_SPEC_FENCES_COUNT 1

#endif
