/* Reflective shadow maps (shaders/photon/photon_rsm.comp): per light entry of the
 * photon tracer, a map of first hits seen from the light with the flux each
 * texel receives and a pyramid of the reflected power (sums of 2 x 2
 * texels, level by level), all built on the GPU. The tracer
 * (photon_trace.comp, PB_PHOTON_PARAM_RSM) warps stratified points through
 * the pyramid (hierarchical warp), so texels are chosen in proportion to that
 * power, and continues each path by BRDF sampling. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/scene/passes.h"
#include "render/photon/photon_rsm.h"
#include "render/scene/scene_plan.h"
#include "shaders/photon_rsm.spv.h"
#include "shaders/photon_rsm_blender.spv.h"
#include "shaders/photon_rsm_rq.spv.h"
#include "shaders/photon_rsm_rq_blender.spv.h"
#include "shared/pb_gpu.h"
#include "shared/pb_rsm.h"


struct pb_photon_rsm {
  const pb_gpu_scene *gs;
  pb_gpu_pipeline pipe;
  pb_gpu_buffer lights, texels;
  uint32_t entries, texel_count, res;
  float center[3], radius, caustic_share;
  uint32_t spec[PB_SPEC_COUNT];
};

pb_result pb_photon_rsm_create(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const uint32_t *light,
                               uint32_t entries, uint32_t res, const float center[3], float radius,
                               float caustic_share, pb_photon_rsm **out) {
  *out = NULL;
  if (!(caustic_share >= 0.0f && caustic_share < 1.0f))
    return pb_fail(PB_ERR_USAGE, "photons: caustic share %g is not in [0, 1)", caustic_share);
  if (res < 1 || res > 4096 || (res & (res - 1)))
    return pb_fail(PB_ERR_USAGE, "photons: RSM resolution %u is not a power of two in 1 .. 4096", res);
  pb_photon_rsm *r = calloc(1, sizeof *r);
  pb_gpu_rsm_light *tab = calloc(entries ? entries : 1, sizeof *tab);
  pb_result rc = PB_OK;
  if (!r || !tab) {
    free(tab);
    free(r);
    return pb_fail(PB_ERR_NOMEM, "photons: out of memory");
  }
  r->gs = gs;
  r->entries = entries;
  r->res = res;
  memcpy(r->center, center, sizeof r->center);
  r->radius = radius;
  r->caustic_share = caustic_share;
  uint64_t total = 0;
  for (uint32_t i = 0; i < entries; ++i) {
    /* Soft lights and the world have no map (count 0): their photons are
     * traced from the light (photon_trace.comp). */
    const pb_light *l = light[i] < s->light_count ? &s->lights[light[i]] : NULL;
    uint32_t kind = l ? pb_light_kind_of(l->type)->flags : 0u;
    uint64_t faces = !l || !pb_light_is_delta(l) ? 0u : kind & PB_LIGHT_OMNI ? 6u : 1u; /* a cube map, or one face */
    tab[i].first = (uint32_t)total;
    tab[i].count = (uint32_t)(faces * res * res);
    tab[i].res = res;
    tab[i].light = light[i];
    tab[i].tan_half = kind & PB_LIGHT_CONE ? tanf(fminf(fmaxf(l->outer_cone, 1e-4f), 1.5f)) : 1.0f;
    tab[i].faces = (uint32_t)faces;
    uint32_t levels = 0;
    while ((1u << levels) < res) ++levels;
    tab[i].levels = levels;
    tab[i].boost = 1.0f;
    total += faces * res * res;
  }
  const pb_gpu_limits *lim = pb_gpu_get_limits(g);
  if (total * sizeof(pb_gpu_rsm_texel) > lim->max_storage_buffer_range || total > 0x7fffffffu) {
    free(tab);
    free(r);
    return pb_fail(PB_ERR_LIMIT, "photons: RSM of %llu texels exceeds maxStorageBufferRange",
                   (unsigned long long)total);
  }
  r->texel_count = (uint32_t)total;
  pb_gpu_buffer_desc ld = {.name = "photons.rsm_lights",
                           .size = (entries ? entries : 1) * sizeof(pb_gpu_rsm_light),
                           .host_visible = 1};
  if ((rc = pb_gpu_buffer_create(g, &ld, &r->lights)) != PB_OK) goto fail;
  if (entries && (rc = pb_gpu_buffer_upload(g, &r->lights, 0, tab, entries * sizeof *tab)) != PB_OK) goto fail;
  pb_gpu_buffer_desc td = {.name = "photons.rsm_texels",
                           .size = (total ? total : 1) * sizeof(pb_gpu_rsm_texel)};
  if ((rc = pb_gpu_buffer_create(g, &td, &r->texels)) != PB_OK) goto fail;
  pb_render_plan plan;
  pb_render_plan_of(s, 0, &plan);
  r->spec[PB_SPEC_HAS_NORMALS] = plan.vertex_normals ? 1u : 0u;
  r->spec[PB_SPEC_TEXTURES] = plan.textures ? 1u : 0u;
  r->spec[PB_SPEC_SPECULAR] = plan.caustic_photons ? 1u : 0u;
  r->spec[PB_SPEC_EMISSIVE] = 0u;
  r->spec[PB_SPEC_ALPHA] = 0u; /* the maps only trace first hits */
  r->spec[PB_SPEC_PRINCIPLED2] = plan.principled2 ? 1u : 0u;
  r->spec[PB_SPEC_CLOSURES] = plan.closures;
  static const pb_kernel_builds k = PB_KERNEL_BUILDS(photon_rsm);
  pb_gpu_pipeline_desc pd = {
      .name = "pass.photon_rsm",
      .binding_count = PB_RSM_BIND_COUNT,
      .push_bytes = sizeof(pb_gpu_rsm_push),
      .spec = r->spec,
      .spec_count = PB_SPEC_COUNT,
  };
  pb_kernel_select(&pd, &k, plan.blender_materials, r->gs->ray_query, PB_BIND_NODES);
  if ((rc = pb_gpu_pipeline_create(g, &pd, &r->pipe)) != PB_OK) goto fail;
  free(tab);
  *out = r;
  return PB_OK;
fail:
  free(tab);
  pb_photon_rsm_destroy(g, r);
  return rc;
}

pb_result pb_photon_rsm_bind(pb_gpu *g, pb_photon_rsm *r, const pb_gpu_buffer *frame) {
  const pb_gpu_scene *gs = r->gs;
  const pb_gpu_buffer *b[PB_RSM_BIND_COUNT] = {
      [PB_BIND_FRAME] = frame, [PB_BIND_NODES] = &gs->nodes, [PB_BIND_TRIS] = &gs->tris,
      [PB_BIND_INDICES] = &gs->indices, [PB_BIND_NORMALS] = &gs->normals, [PB_BIND_UVS] = &gs->uvs,
      [PB_BIND_TRI_MATERIAL] = &gs->tri_material, [PB_BIND_MATERIALS] = &gs->materials,
      [PB_BIND_TEXTURES] = &gs->textures, [PB_BIND_TEXELS] = &gs->texels, [PB_BIND_LIGHTS] = &gs->lights,
      [PB_RSM_BIND_LIGHTS] = &r->lights, [PB_RSM_BIND_TEXELS] = &r->texels, [PB_BIND_POSITIONS] = &gs->positions,
      [PB_BIND_EMITTERS] = &gs->emitters};
  return pb_kernel_bind(g, &r->pipe, b, PB_RSM_BIND_COUNT, pb_gpu_scene_accel(gs));
}

pb_result pb_photon_rsm_record(pb_gpu *g, pb_photon_rsm *r) {
  pb_gpu_rsm_push p;
  memset(&p, 0, sizeof p);
  memcpy(p.scene_center, r->center, sizeof p.scene_center);
  p.scene_radius = r->radius;
  p.light_count = r->entries;
  p.texels = r->texel_count;
  p.caustic_share = r->caustic_share;
  p.mode = PB_RSM_MODE_RENDER;
  pb_result rc;
  if (!r->entries) return PB_OK;
  if ((rc = pb_gpu_dispatch(g, &r->pipe, &p, r->texel_count)) != PB_OK) return rc;
  pb_gpu_barrier(g);
  if (r->caustic_share > 0.0f) {
    /* The specular texels' weights raised to the caustic share (one
     * workgroup per light), before the pyramid sums them. */
    p.mode = PB_RSM_MODE_BOOST;
    if ((rc = pb_gpu_dispatch(g, &r->pipe, &p, r->entries * PB_GPU_WORKGROUP)) != PB_OK) return rc;
    pb_gpu_barrier(g);
  }
  /* The weight pyramid, one level at a time (every light shares res), then
   * each light's total. */
  p.mode = PB_RSM_MODE_PYRAMID;
  for (p.level = 1; (1u << p.level) <= r->res; ++p.level) {
    if ((rc = pb_gpu_dispatch(g, &r->pipe, &p, r->texel_count)) != PB_OK) return rc;
    pb_gpu_barrier(g);
  }
  p.mode = PB_RSM_MODE_TOTAL; /* one workgroup per light */
  if ((rc = pb_gpu_dispatch(g, &r->pipe, &p, r->entries * PB_GPU_WORKGROUP)) != PB_OK) return rc;
  pb_gpu_barrier(g);
  return PB_OK;
}

const pb_gpu_buffer *pb_photon_rsm_lights(const pb_photon_rsm *r) { return &r->lights; }
const pb_gpu_buffer *pb_photon_rsm_texels(const pb_photon_rsm *r) { return &r->texels; }
uint32_t pb_photon_rsm_texel_count(const pb_photon_rsm *r) { return r->texel_count; }

pb_result pb_photon_rsm_coverage(pb_gpu *g, const pb_photon_rsm *r, int auto_mode, uint32_t *mapped,
                                 float *min_coverage) {
  *mapped = 0;
  *min_coverage = 1.0f;
  if (!r->entries) return PB_OK;
  pb_gpu_rsm_light *tab = calloc(r->entries, sizeof *tab);
  if (!tab) return pb_fail(PB_ERR_NOMEM, "photons: out of memory");
  pb_result rc = pb_gpu_buffer_download(g, &r->lights, 0, tab, r->entries * sizeof *tab);
  for (uint32_t i = 0; rc == PB_OK && i < r->entries; ++i) {
    if (!tab[i].count || !(tab[i].total > 0.0f)) continue;
    if (tab[i].coverage < *min_coverage) *min_coverage = tab[i].coverage;
    if (!auto_mode || tab[i].coverage < PB_RSM_AUTO_COVERAGE) ++*mapped;
  }
  free(tab);
  return rc;
}

pb_result pb_photon_rsm_boost(pb_gpu *g, const pb_photon_rsm *r, float *max_boost) {
  *max_boost = 1.0f;
  if (!r->entries) return PB_OK;
  pb_gpu_rsm_light *tab = calloc(r->entries, sizeof *tab);
  if (!tab) return pb_fail(PB_ERR_NOMEM, "photons: out of memory");
  pb_result rc = pb_gpu_buffer_download(g, &r->lights, 0, tab, r->entries * sizeof *tab);
  for (uint32_t i = 0; rc == PB_OK && i < r->entries; ++i)
    if (tab[i].count && tab[i].boost > *max_boost) *max_boost = tab[i].boost;
  free(tab);
  return rc;
}

void pb_photon_rsm_destroy(pb_gpu *g, pb_photon_rsm *r) {
  if (!r) return;
  pb_gpu_pipeline_destroy(g, &r->pipe);
  pb_gpu_buffer_destroy(g, &r->lights);
  pb_gpu_buffer_destroy(g, &r->texels);
  free(r);
}
