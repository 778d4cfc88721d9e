/* Scene upload: the BVH and the flat arrays of pb_scene, converted to the
 * structs of shaders/shared/pb_gpu.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "scene/emitters.h"
#include "scene/world.h"
#include "render/render.h"
#include "shared/pb_principled2_tables.h"

void pb_gpu_scene_destroy(pb_gpu *g, pb_gpu_scene *gs) {
  if (!gs) return;
  pb_gpu_buffer *b[] = {&gs->nodes, &gs->tris, &gs->indices, &gs->positions, &gs->normals, &gs->uvs,
                        &gs->tri_material, &gs->materials, &gs->textures, &gs->texels, &gs->lights,
                        &gs->emitters, &gs->world};
  for (size_t i = 0; i < sizeof b / sizeof *b; ++i) pb_gpu_buffer_destroy(g, b[i]);
  pb_gpu_accel_destroy(g, &gs->accel);
  pb_bvh_destroy(&gs->bvh);
  memset(gs, 0, sizeof *gs);
}

/* Creates a buffer of at least 16 bytes and fills it with `size` bytes. */
static pb_result make(pb_gpu *g, pb_gpu_buffer *b, const char *name, const void *data, uint64_t size) {
  pb_gpu_buffer_desc d = {.name = name, .size = size < 16 ? 16 : size};
  pb_result r = pb_gpu_buffer_create(g, &d, b);
  if (r != PB_OK) return r;
  if (!data || !size) return pb_gpu_buffer_fill_zero(g, b);
  return pb_gpu_buffer_upload(g, b, 0, data, size);
}

/* Creates a buffer of `capacity` (>= size) bytes holding `size` bytes of data. */
static pb_result make_cap(pb_gpu *g, pb_gpu_buffer *b, const char *name, const void *data, uint64_t size,
                          uint64_t capacity) {
  pb_gpu_buffer_desc d = {.name = name, .size = capacity < 16 ? 16 : capacity};
  pb_result r = pb_gpu_buffer_create(g, &d, b);
  if (r != PB_OK) return r;
  if (!data || !size) return pb_gpu_buffer_fill_zero(g, b);
  if (size < capacity && (r = pb_gpu_buffer_fill_zero(g, b)) != PB_OK) return r;
  return pb_gpu_buffer_upload(g, b, 0, data, size);
}

static uint32_t emissive_triangles(const pb_scene *s) {
  uint32_t n = 0;
  for (uint32_t t = 0; t < s->triangle_count; ++t)
    if (pb_material_is_emissive(&s->materials[s->triangle_material[t]])) n++;
  return n;
}

static void convert_lights(const pb_scene *s, pb_gpu_light *lights) {
  for (uint32_t i = 0; i < s->light_count; ++i) pb_light_pack_gpu(&s->lights[i], &lights[i]);
}

/* The world's buffer: pb_gpu_world, then per texel (R, G, B, conditional
 * CDF) and the marginal CDF (shared/pb_gpu.h), from the table both
 * renderers sample (scene/world.h). Errors: PB_ERR_LIMIT when it exceeds
 * the device's storage-buffer range (name the map: a smaller one fits),
 * PB_ERR_NOMEM. */
static pb_result make_world(pb_gpu *g, const pb_scene *s, pb_gpu_buffer *out) {
  const pb_world *w = &s->world;
  pb_gpu_world h;
  memset(&h, 0, sizeof h);
  pb_world_dist dist;
  memset(&dist, 0, sizeof dist);
  if (w->present) {
    h.flags = PB_GPU_WORLD_PRESENT;
    if (s->film_opaque && !w->hidden_from_camera) h.flags |= PB_GPU_WORLD_CAMERA;
    memcpy(h.color, w->color, sizeof h.color);
    float *rows[3] = {h.map_to0, h.map_to1, h.map_to2};
    for (int r = 0; r < 3; ++r) memcpy(rows[r], w->env_to_map + 3 * r, 3 * sizeof(float));
  }
  uint64_t floats = 0;
  if (w->present && w->env) {
    pb_result r = pb_world_dist_build(w, &dist);
    if (r != PB_OK) return r;
    h.flags |= PB_GPU_WORLD_MAP | (dist.width ? PB_GPU_WORLD_SAMPLED : 0u);
    h.width = w->env_width;
    h.height = w->env_height;
    h.scale = w->env_scale;
    uint64_t texels = (uint64_t)w->env_width * w->env_height;
    h.marg_offset = (uint32_t)(4 * texels);
    floats = 4 * texels + w->env_height + 1;
  }
  uint64_t bytes = sizeof h + floats * sizeof(float);
  const pb_gpu_limits *lim = pb_gpu_get_limits(g);
  if (bytes > lim->max_storage_buffer_range || 4 * (uint64_t)h.width * h.height > UINT32_MAX) {
    pb_world_dist_destroy(&dist);
    return pb_fail(PB_ERR_LIMIT,
                   "%s: the world map '%s' (%ux%u) needs %llu bytes on the GPU, over the device's "
                   "maxStorageBufferRange of %llu bytes; use a smaller map",
                   s->path ? s->path : "scene", w->env_name, w->env_width, w->env_height,
                   (unsigned long long)bytes, (unsigned long long)lim->max_storage_buffer_range);
  }
  uint8_t *buf = calloc(1, bytes);
  if (!buf) {
    pb_world_dist_destroy(&dist);
    return pb_fail(PB_ERR_NOMEM, "out of memory for the world's GPU buffer (%llu bytes)", (unsigned long long)bytes);
  }
  memcpy(buf, &h, sizeof h);
  float *data = (float *)(buf + sizeof h);
  if (floats) {
    uint32_t W = w->env_width, H = w->env_height;
    for (uint32_t y = 0; y < H; ++y)
      for (uint32_t x = 0; x < W; ++x) {
        size_t i = (size_t)y * W + x;
        memcpy(data + 4 * i, w->env + 3 * i, 3 * sizeof(float));
        data[4 * i + 3] = dist.width ? dist.cond[(size_t)y * (W + 1) + x] : 0.0f;
      }
    for (uint32_t y = 0; y <= H; ++y) data[h.marg_offset + y] = dist.width ? dist.marg[y] : 0.0f;
  }
  pb_world_dist_destroy(&dist);
  pb_result r = make(g, out, "scene.world", buf, bytes);
  free(buf);
  return r;
}

/* The emitter table (pb_gpu_emitter) from the scene's (scene/emitters.h),
 * which the reference samples too. The CDF is stored as float; `pick` is the
 * difference of consecutive stored values, the probability the shader's
 * search actually realises. */
static pb_result build_emitters(const pb_scene *s, pb_gpu_emitter **out, uint32_t *count) {
  *out = NULL;
  *count = 0;
  pb_emitter_table t;
  pb_result r = pb_emitter_table_build(s, &t);
  if (r != PB_OK || !t.count) return r;
  pb_gpu_emitter *e = calloc(t.count, sizeof *e);
  if (!e) {
    pb_emitter_table_destroy(&t);
    return pb_fail(PB_ERR_NOMEM, "out of memory for %u emitters", t.count);
  }
  for (uint32_t i = 0; i < t.count; ++i) {
    e[i].prim = t.prim[i];
    e[i].area = t.area[i];
    e[i].cdf = (float)t.cdf[i];
  }
  for (uint32_t i = 0; i < t.count; ++i) e[i].pick = (i + 1 < t.count ? e[i + 1].cdf : 1.0f) - e[i].cdf;
  *count = t.count;
  pb_emitter_table_destroy(&t);
  *out = e;
  return PB_OK;
}

/* The GPU's material slots are pb_scene's. */
#define PB_SAME(a, b) ((int)(a) == (int)(b))
_Static_assert(PB_SAME(PB_GPU_MODEL_PRINCIPLED, PB_MODEL_PRINCIPLED) && PB_SAME(PB_GPU_MODEL_DIFFUSE, PB_MODEL_DIFFUSE) &&
                   PB_SAME(PB_GPU_MODEL_EMISSION, PB_MODEL_EMISSION) && PB_SAME(PB_GPU_MODEL_HOLDOUT, PB_MODEL_HOLDOUT),
               "pb_gpu_material.model");
_Static_assert(PB_SAME(PB_GPU_NODE_PRINCIPLED, PB_NODE_PRINCIPLED) && PB_SAME(PB_GPU_NODE_GLOSSY, PB_NODE_GLOSSY) &&
                   PB_SAME(PB_GPU_NODE_GLASS, PB_NODE_GLASS) && PB_SAME(PB_GPU_NODE_REFRACTION, PB_NODE_REFRACTION) &&
                   PB_SAME(PB_GPU_NODE_VELVET, PB_NODE_VELVET),
               "pb_gpu_material.node");
_Static_assert(PB_SAME(PB_GPU_IN_METALLIC, PB_IN_METALLIC) && PB_SAME(PB_GPU_IN_ROUGHNESS, PB_IN_ROUGHNESS) &&
                   PB_SAME(PB_GPU_IN_IOR, PB_IN_IOR) && PB_SAME(PB_GPU_IN_ALPHA, PB_IN_ALPHA) &&
                   PB_SAME(PB_GPU_IN_SUBSURFACE, PB_IN_SUBSURFACE) && (int)PB_IN_COUNT <= (int)PB_GPU_IN_SLOTS &&
                   PB_SAME(PB_GPU_IN_SPECULAR_IOR_LEVEL, PB_IN_SPECULAR_IOR_LEVEL) &&
                   PB_SAME(PB_GPU_IN_EMISSION_STRENGTH, PB_IN_EMISSION_STRENGTH) &&
                   PB_SAME(PB_GPU_IN_THIN_FILM_THICKNESS, PB_IN_THIN_FILM_THICKNESS) &&
                   PB_SAME(PB_GPU_IN_THIN_FILM_IOR, PB_IN_THIN_FILM_IOR) &&
                   PB_SAME(PB_GPU_IN_CONDUCTOR_N, PB_IN_CONDUCTOR_N_R) && PB_SAME(PB_GPU_IN_MIX_FAC, PB_IN_MIX_FAC) &&
                   PB_SAME(PB_GPU_MIX_FAC_FRESNEL, PB_MIX_FAC_FRESNEL) &&
                   PB_SAME(PB_GPU_MIX_FAC_LAYER_FRESNEL, PB_MIX_FAC_LAYER_FRESNEL) &&
                   PB_SAME(PB_GPU_MIX_FAC_LAYER_FACING, PB_MIX_FAC_LAYER_FACING) &&
                   PB_SAME(PB_GPU_MIX_FAC_ADD, PB_MIX_FAC_ADD) &&
                   (int)PB_GPU_IN_V1_SLOTS > (int)PB_IN_SUBSURFACE &&
                   PB_SAME(PB_GPU_IN_SLOTS, sizeof ((pb_gpu_material *)0)->in_value / sizeof(float)),
               "pb_gpu_material.in_value");
#undef PB_SAME

/* Cycles' tables for Principled v2 (shared/pb_principled2_tables.h) as the
 * GPU reads them: concatenated at their PB_P2T_* offsets, as float bits. */
static void pack_principled2_tables(uint32_t *dst) {
  static const struct {
    const float *t;
    uint32_t at, n;
  } tab[] = {{pb_ggx_E, PB_P2T_GGX_E, PB_P2T_GGX_EAVG - PB_P2T_GGX_E},
             {pb_ggx_Eavg, PB_P2T_GGX_EAVG, PB_P2T_GGX_GLASS_E - PB_P2T_GGX_EAVG},
             {pb_ggx_glass_E, PB_P2T_GGX_GLASS_E, PB_P2T_GGX_GLASS_EAVG - PB_P2T_GGX_GLASS_E},
             {pb_ggx_glass_Eavg, PB_P2T_GGX_GLASS_EAVG, PB_P2T_GGX_GLASS_INV_E - PB_P2T_GGX_GLASS_EAVG},
             {pb_ggx_glass_inv_E, PB_P2T_GGX_GLASS_INV_E, PB_P2T_GGX_GLASS_INV_EAVG - PB_P2T_GGX_GLASS_INV_E},
             {pb_ggx_glass_inv_Eavg, PB_P2T_GGX_GLASS_INV_EAVG, PB_P2T_GGX_GEN_SCHLICK_IOR_S - PB_P2T_GGX_GLASS_INV_EAVG},
             {pb_ggx_gen_schlick_ior_s, PB_P2T_GGX_GEN_SCHLICK_IOR_S, PB_P2T_GGX_GEN_SCHLICK_S - PB_P2T_GGX_GEN_SCHLICK_IOR_S},
             {pb_ggx_gen_schlick_s, PB_P2T_GGX_GEN_SCHLICK_S, PB_P2T_SHEEN_LTC - PB_P2T_GGX_GEN_SCHLICK_S},
             {pb_sheen_ltc, PB_P2T_SHEEN_LTC, PB_P2T_COUNT - PB_P2T_SHEEN_LTC}};
  _Static_assert(sizeof pb_ggx_E / sizeof(float) == PB_P2T_GGX_EAVG - PB_P2T_GGX_E, "table layout");
  _Static_assert(sizeof pb_sheen_ltc / sizeof(float) == PB_P2T_COUNT - PB_P2T_SHEEN_LTC, "table layout");
  for (size_t k = 0; k < sizeof tab / sizeof tab[0]; ++k) memcpy(dst + tab[k].at, tab[k].t, tab[k].n * sizeof(float));
}

static uint32_t tex_index(int32_t t, uint32_t count) {
  return t >= 0 && (uint32_t)t < count ? (uint32_t)t : PB_GPU_NO_TEXTURE;
}

/* The geometry: the BVH, indices, positions, normals (and tangents), uvs
 * (and TEXCOORD_1, COLOR_0), the triangles' materials. */
static pb_result upload_geometry(pb_gpu *g, const pb_scene *s, pb_gpu_scene *gs) {
  pb_result r;
  r = pb_bvh_build(s, &gs->bvh);
  if (r != PB_OK) return r;
  pb_log_verbose("gpu: BVH of %u triangles: %u nodes, depth %u, %.1f ms", gs->bvh.tri_count,
                 gs->bvh.node_count, gs->bvh.depth, gs->bvh.build_s * 1e3);
  /* An animated scene may be rebuilt (pb_gpu_scene_update): room for the
   * largest tree a build can make (pb_bvh_build's own allocation). */
  gs->node_capacity = s->anim ? PB_BVH_WIDTH * gs->bvh.tri_count + 1 : gs->bvh.node_count;
  if (gs->node_capacity < gs->bvh.node_count) gs->node_capacity = gs->bvh.node_count;
  gs->sah_built = gs->sah = pb_bvh_sah_cost(&gs->bvh);
  gs->vertex_count = s->vertex_count;
  gs->triangle_count = s->triangle_count;
  r = make_cap(g, &gs->nodes, "scene.bvh_nodes", gs->bvh.nodes, (uint64_t)gs->bvh.node_count * sizeof(pb_gpu_bvh_node),
               (uint64_t)gs->node_capacity * sizeof(pb_gpu_bvh_node));
  if (r != PB_OK) return r;
  r = make(g, &gs->tris, "scene.bvh_triangles", gs->bvh.tris, (uint64_t)gs->bvh.tri_count * sizeof(pb_gpu_tri));
  if (r != PB_OK) return r;
  r = make(g, &gs->indices, "scene.indices", s->triangles, (uint64_t)s->triangle_count * 12);
  if (r != PB_OK) return r;
  r = make(g, &gs->positions, "scene.positions", s->positions, (uint64_t)s->vertex_count * 12);
  if (r != PB_OK) return r;
  if (pb_gpu_get_limits(g)->ray_query) { /* ray queries: the passes trace this instead of the BVH */
    pb_gpu_accel_desc ad = {.name = "scene.accel",
                            .positions = s->vertex_count ? &s->positions[0][0] : NULL,
                            .vertex_count = s->vertex_count,
                            .indices = s->triangle_count ? &s->triangles[0][0] : NULL,
                            .triangle_count = s->triangle_count,
                            .updatable = s->anim != NULL};
    if ((r = pb_gpu_accel_create(g, &ad, &gs->accel)) != PB_OK) return r;
    gs->ray_query = 1;
  }
  gs->has_normals = s->normals != NULL;
  if (s->tangents && s->uvs && (s->features & (PB_FEATURE_NORMAL_MAPS | PB_FEATURE_ANISOTROPY)) && s->vertex_count &&
      (uint64_t)s->vertex_count * 7 < UINT32_MAX) {
    /* Normal maps: the tangents (float[4] per vertex) follow the normals in
     * the same buffer, from float index tangent_base (pb_gpu_frame), so the
     * passes keep their bindings and scenes without normal maps pay
     * nothing. */
    uint64_t nf = (uint64_t)s->vertex_count * 3, tf = (uint64_t)s->vertex_count * 4;
    float *nt = calloc(nf + tf, sizeof *nt);
    if (!nt) return pb_fail(PB_ERR_NOMEM, "out of memory for the normals and tangents");
    if (s->normals) memcpy(nt, s->normals, nf * sizeof *nt);
    memcpy(nt + nf, s->tangents, tf * sizeof *nt);
    r = make(g, &gs->normals, "scene.normals_tangents", nt, (nf + tf) * sizeof *nt);
    free(nt);
    gs->tangent_base = (uint32_t)nf;
  } else {
    r = make(g, &gs->normals, "scene.normals", s->normals, s->normals ? (uint64_t)s->vertex_count * 12 : 0);
  }
  if (r != PB_OK) return r;
  if ((s->uvs1 || s->colors) && s->vertex_count && (uint64_t)s->vertex_count * 8 < UINT32_MAX) {
    /* TEXCOORD_1 and COLOR_0 follow TEXCOORD_0 in the same buffer, from the
     * float indices uv1_base and color_base (pb_gpu_frame), as the tangents
     * follow the normals: the passes keep their bindings, and scenes
     * without them pay nothing. */
    uint64_t n0 = (uint64_t)s->vertex_count * 2, n1 = s->uvs1 ? n0 : 0, nc = s->colors ? (uint64_t)s->vertex_count * 4 : 0;
    float *u = calloc(n0 + n1 + nc, sizeof *u);
    if (!u) return pb_fail(PB_ERR_NOMEM, "out of memory for the uvs and vertex colours");
    if (s->uvs) memcpy(u, s->uvs, n0 * sizeof *u);
    if (s->uvs1) memcpy(u + n0, s->uvs1, n1 * sizeof *u);
    if (s->colors) memcpy(u + n0 + n1, s->colors, nc * sizeof *u);
    r = make(g, &gs->uvs, "scene.uvs_colors", u, (n0 + n1 + nc) * sizeof *u);
    free(u);
    gs->uv1_base = s->uvs1 ? (uint32_t)n0 : 0;
    gs->color_base = s->colors ? (uint32_t)(n0 + n1) : 0;
  } else {
    r = make(g, &gs->uvs, "scene.uvs", s->uvs, s->uvs ? (uint64_t)s->vertex_count * 8 : 0);
  }
  if (r != PB_OK) return r;
  return make(g, &gs->tri_material, "scene.triangle_material", s->triangle_material, (uint64_t)s->triangle_count * 4);
}

/* One material as the passes read it (pb_gpu_material). */
static void convert_material(const pb_scene *s, const pb_material *m, pb_gpu_material *o) {
  memcpy(o->base_color, m->base_color, sizeof o->base_color);
  memcpy(o->emissive, m->emissive, sizeof o->emissive);
  memcpy(o->specular_color, m->specular_color, sizeof o->specular_color);
  o->base_color_tex = tex_index(m->base_color_tex, s->texture_count);
  o->metallic_roughness_tex = tex_index(m->metallic_roughness_tex, s->texture_count);
  o->emissive_tex = pb_material_is_emissive(m) ? tex_index(m->emissive_tex, s->texture_count) : PB_GPU_NO_TEXTURE;
  if (!pb_material_is_emissive(m)) memset(o->emissive, 0, sizeof o->emissive);
  o->metallic = m->metallic;
  o->roughness = m->roughness;
  o->transmission = m->transmission;
  o->ior = m->ior;
  o->specular = m->specular;
  o->flags = (m->double_sided ? PB_GPU_MAT_DOUBLE_SIDED : 0) | (m->unlit ? PB_GPU_MAT_UNLIT : 0) |
             (m->blender.base_from_vertex_color ? PB_GPU_MAT_VERTEX_COLOR : 0) |
             (m->blender.normal_map_cycles4 ? PB_GPU_MAT_NORMAL_MAP_CYCLES4 : 0) |
             (m->blender.oren_nayar_ms ? PB_GPU_MAT_OREN_NAYAR_MS : 0) |
           (m->blender.conductor ? PB_GPU_MAT_CONDUCTOR : 0);
  memcpy(o->attenuation, m->attenuation, sizeof o->attenuation);
  o->normal_tex = s->tangents && s->uvs ? tex_index(m->normal_tex, s->texture_count) : PB_GPU_NO_TEXTURE;
  o->normal_scale = m->normal_scale;
  const pb_blender_material *b = &m->blender;
  o->model = (uint32_t)b->model;
  o->distribution = b->distribution == PB_DISTRIBUTION_MULTI_GGX  ? PB_GPU_DISTRIBUTION_MULTI_GGX
                    : b->distribution == PB_DISTRIBUTION_BECKMANN ? PB_GPU_DISTRIBUTION_BECKMANN
                                                                   : PB_GPU_DISTRIBUTION_GGX;
  o->subsurface_color_tex = tex_index(b->subsurface_color_tex, s->texture_count);
  memcpy(o->subsurface_color, b->subsurface_color, sizeof o->subsurface_color);
  o->normal_strength = b->normal_strength;
  o->principled_v2 = (uint32_t)b->principled_v2;
  memcpy(o->specular_tint, b->specular_tint, sizeof o->specular_tint);
  memcpy(o->coat_tint, b->coat_tint, sizeof o->coat_tint);
  memcpy(o->sheen_tint, b->sheen_tint, sizeof o->sheen_tint);
  memcpy(o->subsurface_radius, b->subsurface_radius, sizeof o->subsurface_radius);
  o->specular_tint_tex = tex_index(b->specular_tint_tex, s->texture_count);
  o->coat_tint_tex = tex_index(b->coat_tint_tex, s->texture_count);
  o->sheen_tint_tex = tex_index(b->sheen_tint_tex, s->texture_count);
  o->coat_normal_tex = s->tangents && s->uvs ? tex_index(b->coat_normal_tex, s->texture_count) : PB_GPU_NO_TEXTURE;
  o->coat_normal_strength = b->coat_normal_strength;
  o->subsurface_method = (uint32_t)b->subsurface_method;
  o->g2_correlated = (uint32_t)b->g2_correlated;
  o->bump_model = (uint32_t)b->bump_model;
  o->node = (uint32_t)b->node;
  o->mix_with = b->mix_with <= s->material_count ? b->mix_with : 0;
  o->mix_fac = (uint32_t)b->mix_fac;
  for (int k = 0; k < (int)PB_GPU_IN_SLOTS; ++k) {
    o->in_value[k] = k < PB_IN_COUNT ? b->input[k] : 0.0f;
    uint32_t t = k < PB_IN_COUNT ? tex_index(b->input_tex[k].tex, s->texture_count) : PB_GPU_NO_TEXTURE;
    o->in_tex[k] = t == PB_GPU_NO_TEXTURE || t > PB_GPU_INPUT_TEX_INDEX
                       ? PB_GPU_NO_TEXTURE
                       : t | (b->input_tex[k].channel << PB_GPU_INPUT_TEX_CHANNEL_SHIFT);
  }
}

/* The texture table and the texels (8-bit RGBA or half RGBA, packed). */
static void pack_textures(const pb_scene *s, const pb_gpu_scene *gs, pb_gpu_texture *texs, uint32_t *texels) {
  uint32_t off = 0;
  for (uint32_t i = 0; i < s->texture_count; ++i) {
    const pb_texture *t = &s->textures[i];
    uint64_t n = (uint64_t)t->width * t->height;
    texs[i] = (pb_gpu_texture){.offset = off, .width = t->width, .height = t->height,
                               .flags = (t->srgb && !t->rgbah ? PB_GPU_TEX_SRGB : 0) | (t->nearest ? PB_GPU_TEX_NEAREST : 0) |
                                        (t->rgbah ? PB_GPU_TEX_HALF : 0),
                               .wrap_s = (uint32_t)t->wrap_s, .wrap_t = (uint32_t)t->wrap_t,
                               .texcoord = t->texcoord == 1 && gs->uv1_base ? 1u : 0u,
                               .xform_u = {1, 0, 0, 0}, .xform_v = {0, 1, 0, 0}};
    if (t->uv_transformed)
      for (int k = 0; k < 3; ++k) texs[i].xform_u[k] = t->uv_xform[k], texs[i].xform_v[k] = t->uv_xform[3 + k];
    if (t->rgbah) { /* R | G << 16, B | A << 16: unpackHalf2x16's order */
      for (uint64_t k = 0; k < 2 * n; ++k)
        texels[off + k] = (uint32_t)t->rgbah[2 * k] | (uint32_t)t->rgbah[2 * k + 1] << 16;
      n *= 2;
    } else {
      for (uint64_t k = 0; k < n; ++k) {
        const uint8_t *p = t->rgba8 + 4 * k;
        texels[off + k] = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
      }
    }
    off += (uint32_t)n;
  }
}

/* The emitter table, with room for every emissive triangle: a pose can
 * give area to one that had none (pb_gpu_scene_update). */
static pb_result upload_emitters(pb_gpu *g, const pb_scene *s, pb_gpu_scene *gs) {
  pb_gpu_emitter *emitters = NULL;
  pb_result r = build_emitters(s, &emitters, &gs->emitter_count);
  if (r != PB_OK) return r;
  gs->emitter_capacity = emissive_triangles(s);
  if (gs->emitter_capacity < gs->emitter_count) gs->emitter_capacity = gs->emitter_count;
  r = make_cap(g, &gs->emitters, "scene.emitters", emitters, (uint64_t)gs->emitter_count * sizeof *emitters,
               (uint64_t)gs->emitter_capacity * sizeof *emitters);
  free(emitters);
  return r;
}

pb_result pb_gpu_scene_create(pb_gpu *g, const pb_scene *s, pb_gpu_scene *gs) {
  memset(gs, 0, sizeof *gs);
  double t0 = pb_time_now();
  pb_gpu_material *mats = NULL;
  pb_gpu_texture *texs = NULL;
  uint32_t *texels = NULL;
  pb_gpu_light *lights = NULL;
  pb_result r;
  const char *path = s->path ? s->path : "scene";
  for (uint32_t t = 0; t < s->triangle_count; ++t)
    if (s->triangle_material[t] >= s->material_count) {
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: triangle %u uses material %u of %u", path, t,
                  s->triangle_material[t], s->material_count);
      goto fail;
    }
  if ((r = upload_geometry(g, s, gs)) != PB_OK) goto fail;
  uint32_t nm = s->material_count ? s->material_count : 1;
  mats = calloc(nm, sizeof *mats);
  uint64_t texel_count = 0;
  for (uint32_t i = 0; i < s->texture_count; ++i) /* a half texel is two words */
    texel_count += (uint64_t)s->textures[i].width * s->textures[i].height * (s->textures[i].rgbah ? 2u : 1u);
  /* Principled v2 materials read Cycles' albedo and sheen tables
   * (PB_P2T_*): they follow the texels in the same buffer, from index
   * principled2_base (pb_gpu_frame; never 0, so 0 means none), so the
   * passes keep their bindings and a scene without v2 materials pays
   * nothing. */
  int v2 = 0;
  for (uint32_t i = 0; i < s->material_count; ++i)
    v2 |= s->materials[i].blender.model == PB_MODEL_PRINCIPLED && s->materials[i].blender.principled_v2;
  uint64_t p2_base = texel_count ? texel_count : 1;
  uint64_t texel_words = v2 ? p2_base + PB_P2T_COUNT : texel_count;
  if (texel_words > UINT32_MAX) {
    r = pb_fail(PB_ERR_LIMIT, "%s: %llu texels exceed the GPU texel index range", path, (unsigned long long)texel_words);
    goto fail;
  }
  texs = calloc(s->texture_count ? s->texture_count : 1, sizeof *texs);
  texels = calloc(texel_words ? texel_words : 1, sizeof *texels);
  lights = calloc(s->light_count ? s->light_count : 1, sizeof *lights);
  if (!mats || !texs || !texels || !lights) {
    r = pb_fail(PB_ERR_NOMEM, "out of memory preparing the scene for the GPU");
    goto fail;
  }
  for (uint32_t i = 0; i < s->material_count; ++i) convert_material(s, &s->materials[i], &mats[i]);
  pack_textures(s, gs, texs, texels);
  if (v2) {
    gs->principled2_base = (uint32_t)p2_base;
    pack_principled2_tables(texels + p2_base);
  }
  convert_lights(s, lights);
  r = make(g, &gs->materials, "scene.materials", mats, (uint64_t)s->material_count * sizeof *mats);
  if (r != PB_OK) goto fail;
  r = make(g, &gs->textures, "scene.textures", texs, (uint64_t)s->texture_count * sizeof *texs);
  if (r != PB_OK) goto fail;
  r = make(g, &gs->texels, "scene.texels", texels, texel_words * 4);
  if (r != PB_OK) goto fail;
  r = make(g, &gs->lights, "scene.lights", lights, (uint64_t)s->light_count * sizeof *lights);
  if (r != PB_OK) goto fail;
  if ((r = upload_emitters(g, s, gs)) != PB_OK) goto fail;
  if ((r = make_world(g, s, &gs->world)) != PB_OK) goto fail;
  if (gs->emitter_count)
    pb_log_verbose("gpu: %u emissive triangles in the light-sampling table", gs->emitter_count);
  gs->light_count = s->light_count;
  gs->material_count = s->material_count;
  gs->texture_count = s->texture_count;
  gs->features = s->features;
  gs->upload_s = pb_time_now() - t0;
  free(mats);
  free(texs);
  free(texels);
  free(lights);
  return PB_OK;
fail:
  free(mats);
  free(texs);
  free(texels);
  free(lights);
  pb_gpu_scene_destroy(g, gs);
  return r;
}

/* Refit against rebuild, measured with bench/anim.c (pb_bench_anim, scenes
 * from bench/anim_scenes.py) on a shared 2-core AMD EPYC VM, Mesa lavapipe
 * 22.3.6 (LLVM 15), 2026-11-30, 640x360 rays, load average 3-5 from other
 * builds (ray rates +-15 %); tables in bench/README.md, "Animated scenes:
 * BVH refit against rebuild":
 *   update, 108-124k triangles: refit 13-16 ms, rebuild 54-81 ms (4-5x;
 *     one outlier pair 32 / 130 ms);
 *   2,230 triangles: 0.23 ms against 0.9-1.2 ms;
 *   random rays, rebuilt tree against the refitted one, by the refit's SAH
 *   cost over the last build's (pb_bvh_sah_cost, AUTO's gauge):
 *     <= 1.19: -11..+18 %, within the noise (sun_atrium's columns turning
 *              and sliding, spot_room's ball and crate, the debris early);
 *     1.32:    +17 % (spot_room_debris, 48 balls flying apart, at 1 s);
 *     2.3-3.9: +64-70 % (the debris through the walls, 2-3 s).
 * Where the rebuild's rays are faster, its extra 40-50 ms is repaid from 0.8e5
 * to 1.8e5 rays per frame, and a frame of pb_render_frame traces more than
 * 1e6 (640x360 primary and shadow rays plus 2^18 photon paths); where the
 * gain is within the noise, the rebuild is not shown to pay at all. So AUTO refits while the ratio stays
 * at most PB_BVH_REFIT_MAX_SAH = 1.2 and rebuilds beyond (the ratio then
 * starts again from the new tree). A caller tracing far fewer rays per frame
 * (a preview) does better with REFIT throughout. */
#ifndef PB_BVH_REFIT_MAX_SAH
#define PB_BVH_REFIT_MAX_SAH 1.2
#endif

pb_result pb_gpu_scene_update(pb_gpu *g, const pb_scene *s, pb_gpu_scene *gs, int mode, double *ms) {
  double t0 = pb_time_now();
  const char *path = s->path ? s->path : "scene";
  if (ms) *ms = 0;
  if (mode != PB_BVH_UPDATE_AUTO && mode != PB_BVH_UPDATE_REFIT && mode != PB_BVH_UPDATE_REBUILD)
    return pb_fail(PB_ERR_USAGE, "%s: pb_gpu_scene_update: mode %d is not AUTO, REFIT or REBUILD", path, mode);
  if (s->vertex_count != gs->vertex_count || s->triangle_count != gs->triangle_count || s->light_count != gs->light_count ||
      s->material_count != gs->material_count)
    return pb_fail(PB_ERR_USAGE,
                   "%s: pb_gpu_scene_update: the scene has %u vertices, %u triangles, %u lights, %u materials; the GPU scene "
                   "was made from %u, %u, %u, %u",
                   path, s->vertex_count, s->triangle_count, s->light_count, s->material_count, gs->vertex_count,
                   gs->triangle_count, gs->light_count, gs->material_count);
  pb_result r = PB_OK;
  int rebuild = mode == PB_BVH_UPDATE_REBUILD;
  if (!rebuild) {
    r = pb_bvh_refit(s, &gs->bvh);
    if (r != PB_OK) { /* a triangle of the tree is no longer finite */
      pb_error_clear();
      rebuild = 1;
    } else {
      gs->sah = pb_bvh_sah_cost(&gs->bvh);
      gs->refits++;
      if (mode == PB_BVH_UPDATE_AUTO && gs->sah > PB_BVH_REFIT_MAX_SAH * gs->sah_built) rebuild = 1;
    }
  }
  if (rebuild) {
    pb_bvh nb;
    r = pb_bvh_build(s, &nb);
    if (r != PB_OK) return r;
    if (nb.node_count > gs->node_capacity || nb.tri_count != gs->bvh.tri_count) {
      uint32_t need = nb.node_count, tris = nb.tri_count;
      pb_bvh_destroy(&nb);
      if (mode == PB_BVH_UPDATE_REBUILD || gs->refits == 0 || tris != gs->bvh.tri_count)
        return pb_fail(PB_ERR_LIMIT,
                       "%s: BVH rebuild needs %u nodes and %u triangles, the GPU scene holds %u and %u (make it from a "
                       "scene with animation)",
                       path, need, tris, gs->node_capacity, gs->bvh.tri_count);
      pb_log_verbose("gpu: BVH rebuild does not fit the node buffer; keeping the refit");
    } else {
      pb_bvh_destroy(&gs->bvh);
      gs->bvh = nb;
      gs->sah_built = gs->sah = pb_bvh_sah_cost(&gs->bvh);
      gs->refits = 0;
    }
  }
  r = pb_gpu_buffer_upload(g, &gs->nodes, 0, gs->bvh.nodes, (uint64_t)gs->bvh.node_count * sizeof(pb_gpu_bvh_node));
  if (r == PB_OK) r = pb_gpu_buffer_upload(g, &gs->tris, 0, gs->bvh.tris, (uint64_t)gs->bvh.tri_count * sizeof(pb_gpu_tri));
  if (r == PB_OK && s->vertex_count)
    r = pb_gpu_buffer_upload(g, &gs->positions, 0, s->positions, (uint64_t)s->vertex_count * 12);
  if (r == PB_OK && gs->ray_query && s->vertex_count) /* refitted or rebuilt as the BVH was */
    r = pb_gpu_accel_update(g, &gs->accel, &s->positions[0][0], !rebuild);
  if (r == PB_OK && s->vertex_count && s->normals)
    r = pb_gpu_buffer_upload(g, &gs->normals, 0, s->normals, (uint64_t)s->vertex_count * 12);
  if (r == PB_OK && gs->tangent_base && s->tangents) /* normal maps: after the normals */
    r = pb_gpu_buffer_upload(g, &gs->normals, (uint64_t)gs->tangent_base * 4, s->tangents,
                             (uint64_t)s->vertex_count * 16);
  if (r != PB_OK) return r;
  if (s->light_count) {
    pb_gpu_light *lights = calloc(s->light_count, sizeof *lights);
    if (!lights) return pb_fail(PB_ERR_NOMEM, "out of memory preparing the scene for the GPU");
    convert_lights(s, lights);
    r = pb_gpu_buffer_upload(g, &gs->lights, 0, lights, (uint64_t)s->light_count * sizeof *lights);
    free(lights);
    if (r != PB_OK) return r;
  }
  if (gs->emitter_capacity) {
    pb_gpu_emitter *emitters = NULL;
    uint32_t count = 0;
    if ((r = build_emitters(s, &emitters, &count)) != PB_OK) return r;
    if (count > gs->emitter_capacity) { /* cannot happen: capacity counts every emissive triangle */
      free(emitters);
      return pb_fail(PB_ERR_INTERNAL, "%s: %u emitters, room for %u", path, count, gs->emitter_capacity);
    }
    if (count) r = pb_gpu_buffer_upload(g, &gs->emitters, 0, emitters, (uint64_t)count * sizeof *emitters);
    free(emitters);
    if (r != PB_OK) return r;
    gs->emitter_count = count;
  }
  if (ms) *ms = (pb_time_now() - t0) * 1e3;
  return PB_OK;
}
