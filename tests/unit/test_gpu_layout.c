/* Shader/host layout test: every struct of shaders/shared/pb_gpu.h has the
 * same member offsets and array stride in the SPIR-V glslc produced (read
 * from the embedded layout_probe shader's decorations) as in C. GPU-free.
 * Also runs the probe through a pipeline when a device exists (validation on),
 * so the module is known to load. */
#include <stddef.h>
#include <string.h>

#include "gpu/gpu.h"
#include "pbtest.h"
#include "shaders/layout_probe.spv.h"
#include "shared/pb_gpu.h"
#include "shared/pb_vsch.h"

typedef struct member {
  const char *type, *name;
  uint32_t offset;
} member;

#define M(T, f) {#T, #f, (uint32_t)offsetof(T, f)}
static const member members[] = {
    M(pb_gpu_bvh_node, lo), M(pb_gpu_bvh_node, first), M(pb_gpu_bvh_node, hi), M(pb_gpu_bvh_node, count),
    M(pb_gpu_tri, p0), M(pb_gpu_tri, prim), M(pb_gpu_tri, p1), M(pb_gpu_tri, pad0), M(pb_gpu_tri, p2),
    M(pb_gpu_tri, pad1),
    M(pb_gpu_ray, org), M(pb_gpu_ray, tmin), M(pb_gpu_ray, dir), M(pb_gpu_ray, tmax),
    M(pb_gpu_hit, t), M(pb_gpu_hit, prim), M(pb_gpu_hit, u), M(pb_gpu_hit, v),
    M(pb_gpu_material, base_color), M(pb_gpu_material, emissive), M(pb_gpu_material, base_color_tex),
    M(pb_gpu_material, specular_color), M(pb_gpu_material, metallic_roughness_tex),
    M(pb_gpu_material, metallic), M(pb_gpu_material, roughness), M(pb_gpu_material, transmission),
    M(pb_gpu_material, ior), M(pb_gpu_material, specular), M(pb_gpu_material, emissive_tex),
    M(pb_gpu_material, flags), M(pb_gpu_material, normal_tex), M(pb_gpu_material, normal_scale),
    M(pb_gpu_material, model), M(pb_gpu_material, distribution), M(pb_gpu_material, subsurface_color_tex),
    M(pb_gpu_material, subsurface_color), M(pb_gpu_material, normal_strength), M(pb_gpu_material, in_value),
    M(pb_gpu_material, in_tex), M(pb_gpu_material, attenuation), M(pb_gpu_material, principled_v2),
    M(pb_gpu_material, specular_tint), M(pb_gpu_material, specular_tint_tex), M(pb_gpu_material, coat_tint),
    M(pb_gpu_material, coat_tint_tex), M(pb_gpu_material, sheen_tint), M(pb_gpu_material, sheen_tint_tex),
    M(pb_gpu_material, subsurface_radius), M(pb_gpu_material, coat_normal_tex),
    M(pb_gpu_material, coat_normal_strength), M(pb_gpu_material, subsurface_method),
    M(pb_gpu_material, g2_correlated), M(pb_gpu_material, bump_model), M(pb_gpu_material, node),
    M(pb_gpu_material, pad0), M(pb_gpu_material, pad1), M(pb_gpu_material, pad2),
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
    M(pb_gpu_camera, position), M(pb_gpu_camera, x0), M(pb_gpu_camera, forward), M(pb_gpu_camera, dx),
    M(pb_gpu_camera, right), M(pb_gpu_camera, y0), M(pb_gpu_camera, up), M(pb_gpu_camera, dy),
    M(pb_gpu_camera, clip_near), M(pb_gpu_camera, clip_far), M(pb_gpu_camera, orthographic),
    M(pb_gpu_camera, projection), M(pb_gpu_camera, aperture), M(pb_gpu_camera, focus), M(pb_gpu_camera, blades),
    M(pb_gpu_camera, blade_rotation), M(pb_gpu_camera, pano0), M(pb_gpu_camera, pano1), M(pb_gpu_camera, pano2),
    M(pb_gpu_camera, pano3), M(pb_gpu_camera, inv_ratio), M(pb_gpu_camera, pad0), M(pb_gpu_camera, pad1),
    M(pb_gpu_camera, pad2),
    M(pb_gpu_frame, cam), M(pb_gpu_frame, width), M(pb_gpu_frame, height), M(pb_gpu_frame, spp), M(pb_gpu_frame, emitter_count), M(pb_gpu_frame, light_count),
    M(pb_gpu_frame, max_specular_depth), M(pb_gpu_frame, seed_lo), M(pb_gpu_frame, seed_hi),
    M(pb_gpu_frame, flags), M(pb_gpu_frame, pixel_count), M(pb_gpu_frame, pixel_base), M(pb_gpu_frame, tangent_base),
    M(pb_gpu_frame, key_x0), M(pb_gpu_frame, key_y0), M(pb_gpu_frame, key_width),
    M(pb_gpu_frame, uv1_base), M(pb_gpu_frame, color_base), M(pb_gpu_frame, glossy_path_alpha2), M(pb_gpu_frame, principled2_base),
    M(pb_gpu_frame, pad2),
    M(pb_gpu_gbuffer, position), M(pb_gpu_gbuffer, prim), M(pb_gpu_gbuffer, wo), M(pb_gpu_gbuffer, u),
    M(pb_gpu_gbuffer, throughput), M(pb_gpu_gbuffer, v), M(pb_gpu_gbuffer, motion_x),
    M(pb_gpu_gbuffer, motion_y), M(pb_gpu_gbuffer, chain), M(pb_gpu_gbuffer, lobes),
    M(pb_gpu_accum, beauty), M(pb_gpu_accum, direct), M(pb_gpu_accum, depth), M(pb_gpu_accum, albedo),
    M(pb_gpu_accum, material), M(pb_gpu_accum, normal), M(pb_gpu_accum, pad0), M(pb_gpu_accum, emission),
    M(pb_gpu_accum, pad1),
    M(pb_gpu_raycast_push, ray_count), M(pb_gpu_raycast_push, any_hit), M(pb_gpu_raycast_push, pad0),
    M(pb_gpu_raycast_push, pad1),
    M(pb_gpu_pass_push, sample_index), M(pb_gpu_pass_push, pad0), M(pb_gpu_pass_push, pad1),
    M(pb_gpu_pass_push, pad2),
    M(pb_gpu_emitter, prim), M(pb_gpu_emitter, cdf), M(pb_gpu_emitter, pick), M(pb_gpu_emitter, area),
    M(pb_gpu_vsch_push, sample_index), M(pb_gpu_vsch_push, flags), M(pb_gpu_vsch_push, level),
    M(pb_gpu_vsch_push, pixels), M(pb_gpu_vsch_push, node_off), M(pb_gpu_vsch_push, triv_off),
    M(pb_gpu_vsch_push, dir_off), M(pb_gpu_vsch_push, pixel_off), M(pb_gpu_vsch_push, photon_off),
    M(pb_gpu_vsch_push, nodes), M(pb_gpu_vsch_push, capacity), M(pb_gpu_vsch_push, pair_cap),
    M(pb_gpu_vsch_push, level_base), M(pb_gpu_vsch_push, radius), M(pb_gpu_vsch_push, footprint_scale),
    M(pb_gpu_vsch_push, host_count), M(pb_gpu_vsch_push, count_from_map), M(pb_gpu_vsch_push, sorted),
    M(pb_gpu_vsch_push, max_groups_x), M(pb_gpu_vsch_push, pad0), M(pb_gpu_vsch_push, pad1),
};
#define S(T) {#T, sizeof(T)}
static const struct {
  const char *type;
  size_t size;
} sizes[] = {S(pb_gpu_bvh_node), S(pb_gpu_tri),     S(pb_gpu_ray),   S(pb_gpu_hit),
             S(pb_gpu_material), S(pb_gpu_texture), S(pb_gpu_light), S(pb_gpu_frame),
             S(pb_gpu_gbuffer),  S(pb_gpu_accum),   S(pb_gpu_raycast_push), S(pb_gpu_pass_push),
             S(pb_gpu_emitter),  S(pb_gpu_world), S(pb_gpu_camera), S(pb_gpu_vsch_push)};

/* ---- a minimal SPIR-V reader ---------------------------------------------- */

enum { OP_NAME = 5, OP_MEMBER_NAME = 6, OP_DECORATE = 71, OP_MEMBER_DECORATE = 72, OP_TYPE_STRUCT = 30,
       OP_TYPE_RUNTIME_ARRAY = 29, DEC_OFFSET = 35, DEC_ARRAY_STRIDE = 6 };

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

/* ArrayStride of the runtime array whose element type is struct id, or -1. */
static long array_stride(uint32_t id) {
  for (size_t i = 5; i < nwords;) {
    uint32_t op = words[i] & 0xffff, len = words[i] >> 16;
    if (op == OP_TYPE_RUNTIME_ARRAY && words[i + 2] == id) {
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

int main(void) {
  CHECK(nwords > 5 && words[0] == 0x07230203u);
  for (size_t i = 0; i < sizeof members / sizeof *members; ++i) {
    uint32_t id = find_struct(members[i].type);
    long off = id ? member_offset(id, members[i].name) : -2;
    if (off != (long)members[i].offset)
      fprintf(stderr, "%s.%s: C offset %u, SPIR-V offset %ld\n", members[i].type, members[i].name,
              members[i].offset, off);
    CHECK_EQ_INT(off, members[i].offset);
  }
  for (size_t i = 0; i < sizeof sizes / sizeof *sizes; ++i) {
    uint32_t id = find_struct(sizes[i].type);
    long stride = id ? array_stride(id) : -2;
    if (stride != (long)sizes[i].size)
      fprintf(stderr, "%s: C size %zu, SPIR-V array stride %ld\n", sizes[i].type, sizes[i].size, stride);
    CHECK_EQ_INT(stride, sizes[i].size);
  }
  /* The probe loads into a pipeline (validation on) when there is a device. */
  pb_gpu *g;
  pb_gpu_desc gd = {.validation = 1};
  if (pb_gpu_create(&gd, &g) == PB_OK) {
    pb_gpu_pipeline p;
    pb_gpu_pipeline_desc pd = {.name = "layout_probe", .spirv = pb_spv_layout_probe,
                               .spirv_bytes = sizeof pb_spv_layout_probe, .binding_count = 16};
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
