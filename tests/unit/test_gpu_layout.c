/* Shader/host layout test: every struct of the headers in shaders/shared/
 * (the PB_STRUCT ... PB_END declarations, compiled both as C and as std430
 * GLSL) has the same member offsets and array stride in the SPIR-V glslc
 * produced (read from the embedded layout_probe shader's decorations) as in
 * C. GPU-free. Coverage is checked too: every struct the headers declare must
 * be in structs[] below, and each listed struct must list as many members as
 * the SPIR-V has, so a struct or member added to a header without a line here
 * fails the test. Also runs the probe through a pipeline when a device exists
 * (validation on), so the module is known to load. */
#include <dirent.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/gpu.h"
#include "pbtest.h"
#include "shaders/layout_probe.spv.h"
#include "shared/pb_accumulate.h"
#include "shared/pb_filter.h"
#include "shared/pb_gpu.h"
#include "shared/pb_image_maps.h"
#include "shared/pb_knn.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_photon.h"
#include "shared/pb_present.h"
#include "shared/pb_resolve.h"
#include "shared/pb_rsm.h"
#include "shared/pb_splat.h"
#include "shared/pb_upsample.h"
#include "shared/pb_vsch.h"

typedef struct member {
  const char *type, *name;
  uint32_t offset;
} member;

/* Every member of every shared struct, in declaration order, padding
 * included, grouped by header. */
#define M(T, f) {#T, #f, (uint32_t)offsetof(T, f)}
static const member members[] = {
    /* pb_accumulate.h */
    M(pb_gpu_accumulate_push, pixels), M(pb_gpu_accumulate_push, k), M(pb_gpu_accumulate_push, inv),
    M(pb_gpu_accumulate_push, flags),
    /* pb_filter.h */
    M(pb_gpu_atrous_push, width), M(pb_gpu_atrous_push, height), M(pb_gpu_atrous_push, mode),
    M(pb_gpu_atrous_push, step), M(pb_gpu_atrous_push, src_half), M(pb_gpu_atrous_push, sigma_z),
    M(pb_gpu_atrous_push, sigma_n), M(pb_gpu_atrous_push, gamma),
    M(pb_gpu_temporal_push, width), M(pb_gpu_temporal_push, height), M(pb_gpu_temporal_push, has_history),
    M(pb_gpu_temporal_push, still), M(pb_gpu_temporal_push, alpha), M(pb_gpu_temporal_push, sigma_z),
    M(pb_gpu_temporal_push, sigma_n), M(pb_gpu_temporal_push, max_history), M(pb_gpu_temporal_push, clamp_gamma),
    M(pb_gpu_temporal_push, pad0), M(pb_gpu_temporal_push, pad1), M(pb_gpu_temporal_push, pad2),
    M(pb_gpu_temporal_stats, surface), M(pb_gpu_temporal_stats, reset), M(pb_gpu_temporal_stats, len_lo),
    M(pb_gpu_temporal_stats, len_hi),
    M(pb_gpu_filter_io_push, pixels), M(pb_gpu_filter_io_push, mode), M(pb_gpu_filter_io_push, flags),
    M(pb_gpu_filter_io_push, pad0),
    M(pb_gpu_shading_push, pixels), M(pb_gpu_shading_push, s_max), M(pb_gpu_shading_push, pad0),
    M(pb_gpu_shading_push, pad1),
    M(pb_gpu_motion_params, cam), M(pb_gpu_motion_params, prev), M(pb_gpu_motion_params, width),
    M(pb_gpu_motion_params, height), M(pb_gpu_motion_params, triangle_count), M(pb_gpu_motion_params, pad0),
    /* pb_gpu.h */
    M(pb_gpu_bvh_node, lo), M(pb_gpu_bvh_node, first), M(pb_gpu_bvh_node, hi), M(pb_gpu_bvh_node, count),
    M(pb_gpu_tri, p0), M(pb_gpu_tri, prim), M(pb_gpu_tri, p1), M(pb_gpu_tri, pad0), M(pb_gpu_tri, p2),
    M(pb_gpu_tri, pad1),
    M(pb_gpu_ray, org), M(pb_gpu_ray, tmin), M(pb_gpu_ray, dir), M(pb_gpu_ray, tmax),
    M(pb_gpu_hit, t), M(pb_gpu_hit, prim), M(pb_gpu_hit, u), M(pb_gpu_hit, v),
    M(pb_gpu_material, base_color), M(pb_gpu_material, emissive), M(pb_gpu_material, base_color_tex),
    M(pb_gpu_material, specular_color), M(pb_gpu_material, metallic_roughness_tex), M(pb_gpu_material, metallic),
    M(pb_gpu_material, roughness), M(pb_gpu_material, transmission), M(pb_gpu_material, ior),
    M(pb_gpu_material, specular), M(pb_gpu_material, emissive_tex), M(pb_gpu_material, flags),
    M(pb_gpu_material, normal_tex), M(pb_gpu_material, normal_scale), M(pb_gpu_material, model),
    M(pb_gpu_material, distribution), M(pb_gpu_material, subsurface_color_tex), M(pb_gpu_material, subsurface_color),
    M(pb_gpu_material, normal_strength), M(pb_gpu_material, in_value), M(pb_gpu_material, in_tex),
    M(pb_gpu_material, attenuation), M(pb_gpu_material, principled_v2), M(pb_gpu_material, specular_tint),
    M(pb_gpu_material, specular_tint_tex), M(pb_gpu_material, coat_tint), M(pb_gpu_material, coat_tint_tex),
    M(pb_gpu_material, sheen_tint), M(pb_gpu_material, sheen_tint_tex), M(pb_gpu_material, subsurface_radius),
    M(pb_gpu_material, coat_normal_tex), M(pb_gpu_material, coat_normal_strength),
    M(pb_gpu_material, subsurface_method), M(pb_gpu_material, g2_correlated), M(pb_gpu_material, bump_model),
    M(pb_gpu_material, node), M(pb_gpu_material, mix_with), M(pb_gpu_material, mix_fac), M(pb_gpu_material, pad0),
    M(pb_gpu_texture, offset), M(pb_gpu_texture, width), M(pb_gpu_texture, height), M(pb_gpu_texture, flags),
    M(pb_gpu_texture, wrap_s), M(pb_gpu_texture, wrap_t), M(pb_gpu_texture, texcoord), M(pb_gpu_texture, pad1),
    M(pb_gpu_texture, xform_u), M(pb_gpu_texture, xform_v),
    M(pb_gpu_light, position), M(pb_gpu_light, type), M(pb_gpu_light, direction), M(pb_gpu_light, cos_outer),
    M(pb_gpu_light, power), M(pb_gpu_light, cos_inner), M(pb_gpu_light, axis_u), M(pb_gpu_light, radius),
    M(pb_gpu_light, axis_v), M(pb_gpu_light, spot_blend), M(pb_gpu_light, size_u), M(pb_gpu_light, size_v),
    M(pb_gpu_light, tan_spread), M(pb_gpu_light, norm_spread), M(pb_gpu_light, flags), M(pb_gpu_light, cos_half),
    M(pb_gpu_light, pad0), M(pb_gpu_light, pad1),
    M(pb_gpu_world, color), M(pb_gpu_world, flags), M(pb_gpu_world, map_to0), M(pb_gpu_world, map_to1),
    M(pb_gpu_world, map_to2), M(pb_gpu_world, width), M(pb_gpu_world, height), M(pb_gpu_world, scale),
    M(pb_gpu_world, marg_offset),
    M(pb_gpu_emitter, prim), M(pb_gpu_emitter, cdf), M(pb_gpu_emitter, pick), M(pb_gpu_emitter, area),
    M(pb_gpu_camera, position), M(pb_gpu_camera, x0), M(pb_gpu_camera, forward), M(pb_gpu_camera, dx),
    M(pb_gpu_camera, right), M(pb_gpu_camera, y0), M(pb_gpu_camera, up), M(pb_gpu_camera, dy),
    M(pb_gpu_camera, clip_near), M(pb_gpu_camera, clip_far), M(pb_gpu_camera, orthographic),
    M(pb_gpu_camera, projection), M(pb_gpu_camera, aperture), M(pb_gpu_camera, focus), M(pb_gpu_camera, blades),
    M(pb_gpu_camera, blade_rotation), M(pb_gpu_camera, pano0), M(pb_gpu_camera, pano1), M(pb_gpu_camera, pano2),
    M(pb_gpu_camera, pano3), M(pb_gpu_camera, inv_ratio), M(pb_gpu_camera, pad0), M(pb_gpu_camera, pad1),
    M(pb_gpu_camera, pad2),
    M(pb_gpu_frame, cam), M(pb_gpu_frame, width), M(pb_gpu_frame, height), M(pb_gpu_frame, spp),
    M(pb_gpu_frame, emitter_count), M(pb_gpu_frame, light_count), M(pb_gpu_frame, max_specular_depth),
    M(pb_gpu_frame, seed_lo), M(pb_gpu_frame, seed_hi), M(pb_gpu_frame, flags), M(pb_gpu_frame, pixel_count),
    M(pb_gpu_frame, pixel_base), M(pb_gpu_frame, tangent_base), M(pb_gpu_frame, key_x0), M(pb_gpu_frame, key_y0),
    M(pb_gpu_frame, key_width), M(pb_gpu_frame, uv1_base), M(pb_gpu_frame, color_base),
    M(pb_gpu_frame, glossy_path_alpha2), M(pb_gpu_frame, principled2_base), M(pb_gpu_frame, pad2),
    M(pb_gpu_gbuffer, position), M(pb_gpu_gbuffer, prim), M(pb_gpu_gbuffer, wo), M(pb_gpu_gbuffer, u),
    M(pb_gpu_gbuffer, throughput), M(pb_gpu_gbuffer, v), M(pb_gpu_gbuffer, motion_x), M(pb_gpu_gbuffer, motion_y),
    M(pb_gpu_gbuffer, chain), M(pb_gpu_gbuffer, lobes),
    M(pb_gpu_accum, beauty), M(pb_gpu_accum, direct), M(pb_gpu_accum, depth), M(pb_gpu_accum, albedo),
    M(pb_gpu_accum, material), M(pb_gpu_accum, normal), M(pb_gpu_accum, pad0), M(pb_gpu_accum, emission),
    M(pb_gpu_accum, pad1),
    M(pb_gpu_pass_push, sample_index), M(pb_gpu_pass_push, pad0), M(pb_gpu_pass_push, pad1), M(pb_gpu_pass_push, pad2),
    M(pb_gpu_raycast_push, ray_count), M(pb_gpu_raycast_push, any_hit), M(pb_gpu_raycast_push, pad0),
    M(pb_gpu_raycast_push, pad1),
    M(pb_gpu_photon_params, scene_center), M(pb_gpu_photon_params, scene_radius), M(pb_gpu_photon_params, photons),
    M(pb_gpu_photon_params, light_count), M(pb_gpu_photon_params, max_bounces), M(pb_gpu_photon_params, max_depth),
    M(pb_gpu_photon_params, capacity), M(pb_gpu_photon_params, delta), M(pb_gpu_photon_params, smoothing),
    M(pb_gpu_photon_params, smoothing_caustic), M(pb_gpu_photon_params, r_max), M(pb_gpu_photon_params, iteration),
    M(pb_gpu_photon_params, flags), M(pb_gpu_photon_params, stencil_h), M(pb_gpu_photon_params, stencil_depth),
    M(pb_gpu_photon_params, guarded), M(pb_gpu_photon_params, absorbed), M(pb_gpu_photon_params, escaped),
    M(pb_gpu_photon_params, bandwidth_h0), M(pb_gpu_photon_params, bandwidth_p_min),
    M(pb_gpu_photon_params, bandwidth_p_max), M(pb_gpu_photon_params, bandwidth_pad),
    M(pb_gpu_photon_light, power), M(pb_gpu_photon_light, light), M(pb_gpu_photon_light, first),
    M(pb_gpu_photon_light, count), M(pb_gpu_photon_light, diff_scale), M(pb_gpu_photon_light, cos_max),
    M(pb_gpu_photon_light, emitters), M(pb_gpu_photon_light, pad0), M(pb_gpu_photon_light, pad1),
    M(pb_gpu_photon_light, pad2),
    /* pb_image_maps.h */
    M(pb_gpu_image_texel, position), M(pb_gpu_image_texel, prim), M(pb_gpu_image_texel, normal),
    M(pb_gpu_image_texel, material),
    M(pb_gpu_image_map, center), M(pb_gpu_image_map, first),
    M(pb_gpu_image_maps_info, count), M(pb_gpu_image_maps_info, resolution), M(pb_gpu_image_maps_info, march_steps),
    M(pb_gpu_image_maps_info, secant_steps), M(pb_gpu_image_maps_info, bounds_min), M(pb_gpu_image_maps_info, epsilon),
    M(pb_gpu_image_maps_info, bounds_max), M(pb_gpu_image_maps_info, start_offset),
    M(pb_gpu_image_counts, segments), M(pb_gpu_image_counts, hits), M(pb_gpu_image_counts, misses),
    M(pb_gpu_image_counts, escapes), M(pb_gpu_image_counts, type_b), M(pb_gpu_image_counts, type_c),
    M(pb_gpu_image_counts, pad0), M(pb_gpu_image_counts, pad1),
    M(pb_gpu_image_maps_push, first_map), M(pb_gpu_image_maps_push, map_count), M(pb_gpu_image_maps_push, resolution),
    M(pb_gpu_image_maps_push, ray_count),
    M(pb_gpu_image_touch, box_min), M(pb_gpu_image_touch, pad0), M(pb_gpu_image_touch, box_max),
    M(pb_gpu_image_touch, pad1), M(pb_gpu_image_touch, touched),
    /* pb_knn.h */
    M(pb_gpu_knn_push, sample_index), M(pb_gpu_knn_push, flags), M(pb_gpu_knn_push, r_max),
    M(pb_gpu_knn_push, edge_reach),
    /* pb_lbvh.h */
    M(pb_gpu_lbvh_child, lo), M(pb_gpu_lbvh_child, ref), M(pb_gpu_lbvh_child, hi), M(pb_gpu_lbvh_child, count),
    M(pb_gpu_lbvh_node, child),
    M(pb_gpu_lbvh_info, count), M(pb_gpu_lbvh_info, root), M(pb_gpu_lbvh_info, t_auto), M(pb_gpu_lbvh_info, leaves),
    M(pb_gpu_lbvh_info, bmin), M(pb_gpu_lbvh_info, tiles), M(pb_gpu_lbvh_info, bmax), M(pb_gpu_lbvh_info, tiles_done),
    M(pb_gpu_lbvh_info, lo), M(pb_gpu_lbvh_info, area_sum), M(pb_gpu_lbvh_info, hi), M(pb_gpu_lbvh_info, scene_area),
    M(pb_gpu_lbvh_info, stack_overflow), M(pb_gpu_lbvh_info, footprint_scale), M(pb_gpu_lbvh_info, t_fixed),
    M(pb_gpu_lbvh_info, t_computed), M(pb_gpu_lbvh_info, photon_args), M(pb_gpu_lbvh_info, tile_args),
    M(pb_gpu_lbvh_push, capacity), M(pb_gpu_lbvh_push, host_count), M(pb_gpu_lbvh_push, flags),
    M(pb_gpu_lbvh_push, max_groups_x), M(pb_gpu_lbvh_push, scene_area), M(pb_gpu_lbvh_push, footprint_scale),
    M(pb_gpu_lbvh_push, t_fixed), M(pb_gpu_lbvh_push, sorted),
    M(pb_gpu_sort_state, count), M(pb_gpu_sort_state, tiles), M(pb_gpu_sort_state, spine_digits),
    M(pb_gpu_sort_state, pad0), M(pb_gpu_sort_state, tile_args), M(pb_gpu_sort_state, serial_args),
    M(pb_gpu_sort_state, spine_args), M(pb_gpu_sort_state, totals),
    M(pb_gpu_sort_push, shift), M(pb_gpu_sort_push, src), M(pb_gpu_sort_push, dst), M(pb_gpu_sort_push, pass),
    M(pb_gpu_sort_push, count_word), M(pb_gpu_sort_push, capacity), M(pb_gpu_sort_push, max_groups_x),
    M(pb_gpu_sort_push, tile), M(pb_gpu_sort_push, bits), M(pb_gpu_sort_push, pad),
    M(pb_gpu_photon_accum, indirect), M(pb_gpu_photon_accum, caustic),
    M(pb_gpu_photon_nmap, dir), M(pb_gpu_photon_nmap, geo), M(pb_gpu_photon_nmap, ns),
    M(pb_gpu_gather_push, sample_index), M(pb_gpu_gather_push, flags), M(pb_gpu_gather_push, edge_reach),
    M(pb_gpu_gather_push, level),
    /* pb_photon.h */
    M(pb_gpu_photon, position), M(pb_gpu_photon, flags), M(pb_gpu_photon, power), M(pb_gpu_photon, radius),
    M(pb_gpu_photon, wi), M(pb_gpu_photon, normal_extent), M(pb_gpu_photon, normal), M(pb_gpu_photon, path),
    M(pb_gpu_photon, axis_u), M(pb_gpu_photon, ray_length), M(pb_gpu_photon, axis_v), M(pb_gpu_photon, pad1),
    M(pb_gpu_photon_packed, position), M(pb_gpu_photon_packed, normal_extent), M(pb_gpu_photon_packed, power),
    M(pb_gpu_photon_packed, scale), M(pb_gpu_photon_packed, normal_oct), M(pb_gpu_photon_packed, wi_flags),
    M(pb_gpu_photon_packed, axis_u2), M(pb_gpu_photon_packed, axis_v2),
    M(pb_gpu_photon_counts, stored), M(pb_gpu_photon_counts, caustic), M(pb_gpu_photon_counts, emitted),
    M(pb_gpu_photon_counts, overflow), M(pb_gpu_photon_counts, clamped), M(pb_gpu_photon_counts, pad0),
    M(pb_gpu_photon_counts, pad1), M(pb_gpu_photon_counts, pad2),
    /* pb_present.h */
    M(pb_gpu_present_push, pixels), M(pb_gpu_present_push, size), M(pb_gpu_present_push, offset),
    M(pb_gpu_present_push, channels), M(pb_gpu_present_push, lo), M(pb_gpu_present_push, hi),
    M(pb_gpu_present_push, scale), M(pb_gpu_present_push, flags), M(pb_gpu_present_push, data_scale),
    M(pb_gpu_present_push, data_bias), M(pb_gpu_present_push, pad0), M(pb_gpu_present_push, pad1),
    /* pb_resolve.h */
    M(pb_gpu_resolve_kpd, photons_lo), M(pb_gpu_resolve_kpd, photons_hi), M(pb_gpu_resolve_kpd, hits_lo),
    M(pb_gpu_resolve_kpd, hits_hi),
    M(pb_gpu_resolve_push, pixels), M(pb_gpu_resolve_push, inv_spp), M(pb_gpu_resolve_push, flags),
    M(pb_gpu_resolve_push, pad0),
    /* pb_rsm.h */
    M(pb_gpu_rsm_light, first), M(pb_gpu_rsm_light, count), M(pb_gpu_rsm_light, res), M(pb_gpu_rsm_light, light),
    M(pb_gpu_rsm_light, total), M(pb_gpu_rsm_light, tan_half), M(pb_gpu_rsm_light, faces), M(pb_gpu_rsm_light, levels),
    M(pb_gpu_rsm_light, coverage), M(pb_gpu_rsm_light, boost),
    M(pb_gpu_rsm_texel, origin), M(pb_gpu_rsm_texel, prim), M(pb_gpu_rsm_texel, dir), M(pb_gpu_rsm_texel, t),
    M(pb_gpu_rsm_texel, flux), M(pb_gpu_rsm_texel, pyramid), M(pb_gpu_rsm_texel, u), M(pb_gpu_rsm_texel, v),
    M(pb_gpu_rsm_texel, area), M(pb_gpu_rsm_texel, weight),
    M(pb_gpu_rsm_push, scene_center), M(pb_gpu_rsm_push, scene_radius), M(pb_gpu_rsm_push, mode),
    M(pb_gpu_rsm_push, light_count), M(pb_gpu_rsm_push, texels), M(pb_gpu_rsm_push, level),
    M(pb_gpu_rsm_push, caustic_share), M(pb_gpu_rsm_push, pad0), M(pb_gpu_rsm_push, pad1), M(pb_gpu_rsm_push, pad2),
    /* pb_splat.h */
    M(pb_gpu_splat_push, sample_index), M(pb_gpu_splat_push, flags), M(pb_gpu_splat_push, stored),
    M(pb_gpu_splat_push, capacity), M(pb_gpu_splat_push, tile), M(pb_gpu_splat_push, tiles_x),
    M(pb_gpu_splat_push, tiles_y), M(pb_gpu_splat_push, tiles), M(pb_gpu_splat_push, l_max),
    M(pb_gpu_splat_push, n_tile), M(pb_gpu_splat_push, s_max), M(pb_gpu_splat_push, s_n), M(pb_gpu_splat_push, r_min),
    M(pb_gpu_splat_push, r_max), M(pb_gpu_splat_push, footprint_scale), M(pb_gpu_splat_push, max_extent),
    M(pb_gpu_splat_stats, stored), M(pb_gpu_splat_stats, back_facing), M(pb_gpu_splat_stats, outside),
    M(pb_gpu_splat_stats, off_screen), M(pb_gpu_splat_stats, counted), M(pb_gpu_splat_stats, tested),
    M(pb_gpu_splat_stats, splatted), M(pb_gpu_splat_stats, clipped),
    /* pb_upsample.h */
    M(pb_gpu_upsample_push, sample_index), M(pb_gpu_upsample_push, level), M(pb_gpu_upsample_push, levels),
    M(pb_gpu_upsample_push, flags),
    /* pb_vsch.h */
    M(pb_gpu_vsch_push, sample_index), M(pb_gpu_vsch_push, flags), M(pb_gpu_vsch_push, level),
    M(pb_gpu_vsch_push, pixels), M(pb_gpu_vsch_push, node_off), M(pb_gpu_vsch_push, triv_off),
    M(pb_gpu_vsch_push, dir_off), M(pb_gpu_vsch_push, pixel_off), M(pb_gpu_vsch_push, photon_off),
    M(pb_gpu_vsch_push, nodes), M(pb_gpu_vsch_push, capacity), M(pb_gpu_vsch_push, pair_cap),
    M(pb_gpu_vsch_push, level_base), M(pb_gpu_vsch_push, radius), M(pb_gpu_vsch_push, footprint_scale),
    M(pb_gpu_vsch_push, host_count), M(pb_gpu_vsch_push, count_from_map), M(pb_gpu_vsch_push, sorted),
    M(pb_gpu_vsch_push, max_groups_x), M(pb_gpu_vsch_push, pad0), M(pb_gpu_vsch_push, pad1),
};
/* Every shared struct, with its C size (the std430 array stride it must have). */
#define S(T) {#T, sizeof(T)}
static const struct {
  const char *type;
  size_t size;
} structs[] = {
    /* pb_accumulate.h */ S(pb_gpu_accumulate_push),
    /* pb_filter.h */ S(pb_gpu_atrous_push), S(pb_gpu_temporal_push), S(pb_gpu_temporal_stats),
    S(pb_gpu_filter_io_push), S(pb_gpu_shading_push), S(pb_gpu_motion_params),
    /* pb_gpu.h */ S(pb_gpu_bvh_node), S(pb_gpu_tri), S(pb_gpu_ray), S(pb_gpu_hit), S(pb_gpu_material),
    S(pb_gpu_texture), S(pb_gpu_light), S(pb_gpu_world), S(pb_gpu_emitter), S(pb_gpu_camera), S(pb_gpu_frame),
    S(pb_gpu_gbuffer), S(pb_gpu_accum), S(pb_gpu_pass_push), S(pb_gpu_raycast_push), S(pb_gpu_photon_params),
    S(pb_gpu_photon_light),
    /* pb_image_maps.h */ S(pb_gpu_image_texel), S(pb_gpu_image_map), S(pb_gpu_image_maps_info), S(pb_gpu_image_counts),
    S(pb_gpu_image_maps_push), S(pb_gpu_image_touch),
    /* pb_knn.h */ S(pb_gpu_knn_push),
    /* pb_lbvh.h */ S(pb_gpu_lbvh_child), S(pb_gpu_lbvh_node), S(pb_gpu_lbvh_info), S(pb_gpu_lbvh_push),
    S(pb_gpu_sort_state), S(pb_gpu_sort_push), S(pb_gpu_photon_accum), S(pb_gpu_photon_nmap), S(pb_gpu_gather_push),
    /* pb_photon.h */ S(pb_gpu_photon), S(pb_gpu_photon_packed), S(pb_gpu_photon_counts),
    /* pb_present.h */ S(pb_gpu_present_push),
    /* pb_resolve.h */ S(pb_gpu_resolve_kpd), S(pb_gpu_resolve_push),
    /* pb_rsm.h */ S(pb_gpu_rsm_light), S(pb_gpu_rsm_texel), S(pb_gpu_rsm_push),
    /* pb_splat.h */ S(pb_gpu_splat_push), S(pb_gpu_splat_stats),
    /* pb_upsample.h */ S(pb_gpu_upsample_push),
    /* pb_vsch.h */ S(pb_gpu_vsch_push),
};
enum { MEMBER_COUNT = sizeof members / sizeof *members, STRUCT_COUNT = sizeof structs / sizeof *structs };

/* ---- a minimal SPIR-V reader ---------------------------------------------- */

enum { OP_NAME = 5, OP_MEMBER_NAME = 6, OP_DECORATE = 71, OP_MEMBER_DECORATE = 72, OP_TYPE_STRUCT = 30,
       OP_TYPE_ARRAY = 28, OP_TYPE_RUNTIME_ARRAY = 29, DEC_OFFSET = 35, DEC_ARRAY_STRIDE = 6, DEC_BINDING = 33 };

static const uint32_t *words = pb_spv_layout_probe;
static const size_t nwords = sizeof pb_spv_layout_probe / 4;

/* Result id of the struct named `name`, or 0. */
static uint32_t find_struct(const char *name) {
  for (size_t i = 5; i < nwords;) {
    uint32_t op = words[i] & 0xffff, len = words[i] >> 16;
    if (len == 0) break;
    if (op == OP_NAME && strcmp((const char *)&words[i + 2], name) == 0) return words[i + 1];
    i += len;
  }
  return 0;
}

/* Offset of member `member` of struct id, or -1; *index gets its index. */
static long member_offset(uint32_t id, const char *mname) {
  long index = -1;
  for (size_t i = 5; i < nwords;) {
    uint32_t op = words[i] & 0xffff, len = words[i] >> 16;
    if (op == OP_MEMBER_NAME && words[i + 1] == id && strcmp((const char *)&words[i + 3], mname) == 0)
      index = words[i + 2];
    i += len;
  }
  if (index < 0) return -1;
  for (size_t i = 5; i < nwords;) {
    uint32_t op = words[i] & 0xffff, len = words[i] >> 16;
    if (op == OP_MEMBER_DECORATE && words[i + 1] == id && words[i + 2] == (uint32_t)index &&
        words[i + 3] == DEC_OFFSET)
      return words[i + 4];
    i += len;
  }
  return -1;
}

/* Number of members (OpMemberName) of struct id. */
static long member_count(uint32_t id) {
  long n = 0;
  for (size_t i = 5; i < nwords;) {
    uint32_t op = words[i] & 0xffff, len = words[i] >> 16;
    if (op == OP_MEMBER_NAME && words[i + 1] == id) ++n;
    i += len;
  }
  return n;
}

/* ArrayStride of an array (sized or runtime) whose element type is struct id,
 * or -1. */
static long array_stride(uint32_t id) {
  for (size_t i = 5; i < nwords;) {
    uint32_t op = words[i] & 0xffff, len = words[i] >> 16;
    if ((op == OP_TYPE_ARRAY || op == OP_TYPE_RUNTIME_ARRAY) && words[i + 2] == id) {
      uint32_t arr = words[i + 1];
      for (size_t j = 5; j < nwords;) {
        uint32_t op2 = words[j] & 0xffff, len2 = words[j] >> 16;
        if (op2 == OP_DECORATE && words[j + 1] == arr && words[j + 2] == DEC_ARRAY_STRIDE) return words[j + 3];
        j += len2;
      }
    }
    i += len;
  }
  return -1;
}

/* Bindings the probe's buffer blocks use (one block per header): the highest
 * Binding decoration plus one, so the pipeline's layout matches the module. */
static uint32_t binding_count(void) {
  uint32_t n = 0;
  for (size_t i = 5; i < nwords;) {
    uint32_t op = words[i] & 0xffff, len = words[i] >> 16;
    if (op == OP_DECORATE && words[i + 2] == DEC_BINDING && words[i + 3] + 1 > n) n = words[i + 3] + 1;
    i += len;
  }
  return n;
}

/* ---- coverage: the structs the headers declare -------------------------- */

static int listed(const char *type) {
  for (size_t i = 0; i < STRUCT_COUNT; ++i)
    if (strcmp(structs[i].type, type) == 0) return 1;
  return 0;
}

/* Every `PB_STRUCT(name)` that starts a line of shaders/shared/NAME must be in
 * structs[] (the test runs from the source root). Returns how many it found. */
static int check_header(const char *dir, const char *file) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", dir, file);
  FILE *f = fopen(path, "r");
  CHECK(f != NULL);
  if (!f) return 0;
  int found = 0;
  char line[1024];
  while (fgets(line, sizeof line, f)) {
    const char *p = line + strspn(line, " \t");
    if (strncmp(p, "PB_STRUCT(", 10) != 0) continue;
    char name[128];
    size_t n = strcspn(p + 10, ") \t\n");
    if (n == 0 || n >= sizeof name) continue;
    memcpy(name, p + 10, n);
    name[n] = 0;
    ++found;
    if (!listed(name))
      fprintf(stderr, "%s: struct %s is not covered by the layout test: add it to shaders/frame/layout_probe.comp "
              "and its members to members[] and structs[] of tests/unit/test_gpu_layout.c\n", path, name);
    CHECK(listed(name));
  }
  fclose(f);
  return found;
}

static void check_headers(void) {
  const char *dir = "shaders/shared";
  DIR *d = opendir(dir);
  if (!d) fprintf(stderr, "%s: cannot open (the test runs from the source root)\n", dir);
  CHECK(d != NULL);
  if (!d) return;
  int found = 0;
  struct dirent *e;
  while ((e = readdir(d))) {
    size_t n = strlen(e->d_name);
    if (n > 2 && strcmp(e->d_name + n - 2, ".h") == 0) found += check_header(dir, e->d_name);
  }
  closedir(d);
  /* Each listed struct is declared in some header, or this does not compile:
   * so the counts agree exactly when no struct is missing. */
  if (found != STRUCT_COUNT)
    fprintf(stderr, "%s/*.h declare %d structs, the layout test covers %d\n", dir, found, (int)STRUCT_COUNT);
  CHECK_EQ_INT(found, STRUCT_COUNT);
}

int main(void) {
  CHECK(nwords > 5 && words[0] == 0x07230203u);
  check_headers();
  for (size_t i = 0; i < MEMBER_COUNT; ++i) {
    uint32_t id = find_struct(members[i].type);
    long off = id ? member_offset(id, members[i].name) : -2;
    if (off != (long)members[i].offset)
      fprintf(stderr, "%s.%s: C offset %u, SPIR-V offset %ld%s\n", members[i].type, members[i].name,
              members[i].offset, off, off == -2 ? " (struct not in layout_probe.comp)" : "");
    CHECK_EQ_INT(off, members[i].offset);
    if (!listed(members[i].type)) fprintf(stderr, "%s: has members[] but no structs[] entry\n", members[i].type);
    CHECK(listed(members[i].type));
  }
  for (size_t i = 0; i < STRUCT_COUNT; ++i) {
    uint32_t id = find_struct(structs[i].type);
    if (!id) fprintf(stderr, "%s: not in the SPIR-V: declare it in shaders/frame/layout_probe.comp\n", structs[i].type);
    CHECK(id != 0);
    long stride = id ? array_stride(id) : -2;
    if (stride != (long)structs[i].size)
      fprintf(stderr, "%s: C size %zu, SPIR-V array stride %ld\n", structs[i].type, structs[i].size, stride);
    CHECK_EQ_INT(stride, structs[i].size);
    /* Every member the SPIR-V has is listed (a new member without a line in
     * members[] would be checked only through the stride). */
    long listed_members = 0;
    for (size_t j = 0; j < MEMBER_COUNT; ++j) listed_members += strcmp(members[j].type, structs[i].type) == 0;
    long spirv_members = id ? member_count(id) : -2;
    if (spirv_members != listed_members)
      fprintf(stderr, "%s: %ld members in the SPIR-V, %ld in members[]: list every member\n", structs[i].type,
              spirv_members, listed_members);
    CHECK_EQ_INT(spirv_members, listed_members);
  }
  printf("layout: %d structs, %d members checked against the SPIR-V\n", (int)STRUCT_COUNT, (int)MEMBER_COUNT);
  /* The probe loads into a pipeline (validation on) when there is a device. */
  pb_gpu *g;
  pb_gpu_desc gd = {.validation = 1};
  if (pb_gpu_create(&gd, &g) == PB_OK) {
    pb_gpu_pipeline p;
    pb_gpu_pipeline_desc pd = {.name = "layout_probe", .spirv = pb_spv_layout_probe,
                               .spirv_bytes = sizeof pb_spv_layout_probe, .binding_count = binding_count()};
    CHECK_EQ_INT(pb_gpu_pipeline_create(g, &pd, &p), PB_OK);
    pb_gpu_pipeline_destroy(g, &p);
    pb_gpu_pipeline_destroy(g, &p); /* destroy twice: handles were reset */
    /* Malformed descs are refused before any GPU object exists. */
    pb_gpu_pipeline_desc bad = {.name = "bad"};
    CHECK_EQ_INT(pb_gpu_pipeline_create(g, &bad, &p), PB_ERR_INTERNAL);
    pb_error_clear();
    pb_gpu_buffer b;
    pb_gpu_buffer_desc huge = {.name = "huge", .size = pb_gpu_get_limits(g)->max_storage_buffer_range + 1};
    CHECK_EQ_INT(pb_gpu_buffer_create(g, &huge, &b), PB_ERR_LIMIT);
    printf("limit message: %s\n", pb_error_message());
    pb_error_clear();
    pb_gpu_buffer_destroy(g, &b);
    pb_gpu_buffer_destroy(g, NULL);
    CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
    pb_gpu_destroy(g);
  } else {
    printf("no Vulkan device: %s (SPIR-V checks only)\n", pb_error_message());
    pb_error_clear();
  }
  pb_gpu_destroy(NULL);
  return pbt_done();
}
