/* The photon tracer (shaders/photon/photon_trace.comp): emission with the budget
 * split over the lights by power, first hit traced from the light (not
 * stored), BRDF sampling with Russian roulette on the max power ratio,
 * photon differentials and footprints. See the kernel's header comment for
 * the transport and the derivation of the global spacing Delta.
 *
 * Buffers come from the budget: the photon buffer holds photons *
 * min(max_bounces, PB_PHOTON_RECORDS_PER_PATH) records (photon.h), or as
 * many as one storage buffer of the device holds when that is less
 * (lavapipe: 128 MiB, 1.4 M records; a path stores about rho / (1 - rho)
 * records, far fewer than max_bounces); a map that still does not fit (its overflow, counted by
 * the kernel) is PB_ERR_LIMIT, never silently dropped photons. A budget
 * whose paths cannot get one record each is refused up front. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/emitters.h"
#include "render/scene/passes.h"
#include "core/log.h"
#include "render/photon/photon.h"
#include "render/photon/photon_rsm.h"
#include "render/scene/scene_plan.h"
#include "shaders/photon_trace.spv.h"
#include "shaders/photon_trace_blender.spv.h"
#include "shaders/photon_trace_rq.spv.h"
#include "shaders/photon_trace_rq_blender.spv.h"
#include "shaders/photon_trace_images.spv.h"
#include "shaders/photon_trace_images_blender.spv.h"
#include "render/photon/image_maps.h"
#include "shared/pb_photon.h"

enum { PB_PHOTON_MAX_SPECULAR = 8 }; /* delta interactions per path beyond the stored bounces */

struct pb_photon_tracer {
  const pb_gpu_scene *gs;
  pb_gpu_pipeline pipe;
  pb_gpu_buffer frame, params;  /* pb_gpu_frame; params + light table */
  pb_gpu_photon_params p;
  pb_gpu_photon_light *lights;
  uint32_t light_entries;
  uint32_t spec[PB_SPEC_COUNT]; /* the scene's, with PB_SPEC_TRANSMISSION */
  uint64_t seed;
  pb_photon_trace_stats stats;
  pb_photon_rsm *rsm;           /* PB_FIRST_BOUNCE_RSM, else NULL */
  int rsm_ready;                /* the maps are rendered: they depend on the
                                   scene and lights only, so a tracer (one
                                   frame) renders them once and every
                                   iteration warps new points through them */
  pb_photon_trace_desc desc;    /* with defaults filled in */
  int blender;                  /* the scene has Blender materials */
  /* The image-space tracer (pb_photon_tracer_use_image_maps): its maps, the
   * kernel's counters and their values after the last run. */
  const pb_image_maps *images;
  pb_gpu_buffer image_counts;
  pb_gpu_image_counts image_last;
};

static float luminance(const float c[3]) {
  return 0.2126f * fmaxf(c[0], 0.0f) + 0.7152f * fmaxf(c[1], 0.0f) + 0.0722f * fmaxf(c[2], 0.0f);
}

/* The scene's surface area A, m^2 (seed 003's bandwidth; the LBVH's T_auto
 * sums it the same way, lbvh.c). */
static double surface_area(const pb_scene *s) {
  double a = 0.0;
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    const float *p0 = s->positions[s->triangles[t][0]], *p1 = s->positions[s->triangles[t][1]],
                *p2 = s->positions[s->triangles[t][2]];
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) e1[k] = (double)p1[k] - p0[k], e2[k] = (double)p2[k] - p0[k];
    double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    double l = 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (isfinite(l)) a += l;
  }
  return a;
}

static float scene_radius(const pb_scene *s, float center[3]) {
  float d2 = 0.0f;
  for (int c = 0; c < 3; ++c) {
    center[c] = 0.5f * (s->bounds_min[c] + s->bounds_max[c]);
    float e = s->bounds_max[c] - s->bounds_min[c];
    d2 += e * e;
  }
  float r = 0.5f * sqrtf(d2);
  return (r > 1e-6f && isfinite(r)) ? r : 1e-6f;
}

/* Emissive triangles are one photon slot after the lights and the world
 * (an emissive mesh is an area light of its own: a room lit by emission
 * planes had no indirect light; PB_GPU_EMITTER_LIGHT in photon_trace.comp). */
static int emitter_slot(const pb_scene *s) { return (s->features & PB_FEATURE_EMISSIVE) != 0; }

uint32_t pb_photon_slots(const pb_scene *s) {
  return s->light_count + (s->world.present ? 1u : 0u) + (emitter_slot(s) ? 1u : 0u);
}

/* Power of slot i (a light, the world, or the emitters) for the split. */
static double slot_power(const pb_scene *s, uint32_t i, float radius) {
  float pw[3];
  if (i < s->light_count) {
    pb_light_power(&s->lights[i], radius, pw);
  } else if (s->world.present && i == s->light_count) {
    for (int c = 0; c < 3; ++c) pw[c] = (float)M_PI * radius * radius * s->world.integral[c];
  } else {
    double f[3];
    pb_emitter_flux(s, f);
    for (int c = 0; c < 3; ++c) pw[c] = (float)f[c];
  }
  double w = luminance(pw);
  return isfinite(w) ? w : 0.0;
}

void pb_photon_split_budget(const pb_scene *s, uint32_t total, uint32_t *photons, uint32_t *first) {
  float center[3];
  float radius = scene_radius(s, center);
  uint32_t n = pb_photon_slots(s);
  double sum = 0.0;
  for (uint32_t i = 0; i < n; ++i) sum += slot_power(s, i, radius);
  uint64_t given = 0;
  double *rem = calloc(n ? n : 1, sizeof *rem);
  for (uint32_t i = 0; i < n; ++i) {
    double w = slot_power(s, i, radius);
    if (!(sum > 0.0)) w = 0.0;
    double share = sum > 0.0 ? (double)total * w / sum : 0.0;
    photons[i] = (uint32_t)floor(share);
    if (rem) rem[i] = w > 0.0 ? share - floor(share) : -1.0;
    given += photons[i];
  }
  /* Largest remainders get the rest (ties: lower index). */
  while (rem && sum > 0.0 && given < total) {
    uint32_t best = 0;
    for (uint32_t i = 1; i < n; ++i)
      if (rem[i] > rem[best]) best = i;
    if (rem[best] < 0.0) break;
    photons[best]++;
    rem[best] = -0.5; /* one extra at most */
    given++;
  }
  free(rem);
  uint32_t f = 0;
  for (uint32_t i = 0; i < n; ++i) {
    first[i] = f;
    f += photons[i];
  }
}

/* The parts of a tracer that follow the scene's pose: the photon budget
 * split by light power, each light's photon power and differential scale,
 * the scene's centre and radius (directional lights emit from its disc;
 * the default r_max is PB_PHOTON_R_MAX_FACTOR Delta R, photon.h). counts/firsts: scratch of
 * pb_photon_slots entries. */
static void scene_lights(pb_photon_tracer *t, const pb_scene *s, uint32_t *counts, uint32_t *firsts,
                         float center[3], float *radius_out) {
  const pb_photon_trace_desc *d = &t->desc;
  float radius = scene_radius(s, center);
  float delta = 2.0f * sqrtf((float)M_PI / (float)d->photons);
  pb_photon_split_budget(s, d->photons, counts, firsts);
  uint32_t total = 0;
  t->light_entries = 0;
  uint32_t slots = pb_photon_slots(s);
  for (uint32_t i = 0; i < slots; ++i) {
    if (!counts[i]) continue;
    int world = s->world.present && i == s->light_count;
    int emit = i >= s->light_count && !world;
    const pb_light *l = world || emit ? NULL : &s->lights[i];
    pb_gpu_photon_light *e = &t->lights[t->light_entries++];
    memset(e, 0, sizeof *e);
    e->light = world ? PB_GPU_WORLD_LIGHT : emit ? PB_GPU_EMITTER_LIGHT : i;
    e->first = total;
    e->count = counts[i];
    total += counts[i];
    if (emit) {
      /* Lambertian emission over a hemisphere of each emitting side (its
       * solid angle in the differentials, as an area light's cone); the
       * table's count is the GPU scene's (the same pb_emitter_table_build). */
      pb_emitter_table et;
      if (pb_emitter_table_build(s, &et) == PB_OK) e->emitters = et.count;
      pb_emitter_table_destroy(&et);
      for (int c = 0; c < 3; ++c) e->power[c] = (float)(M_PI / counts[i]);
      e->cos_max = 0.0f;
      e->diff_scale = (float)(sqrt(2.0 * M_PI / counts[i]) / delta);
      continue;
    }
    double omega, k, scale;
    float col[3] = {1, 1, 1};
    if (world) {
      /* Parallel rays over the bounding disc, as a sun's (scene/light.c). */
      omega = M_PI * (double)radius * radius; /* disc area */
      scale = omega;
      e->cos_max = 1.0f;
    } else {
      /* The kind's directions and flux per unit intensity (scene/light.h). */
      pb_light_emission em;
      pb_light_kind_of(l->type)->emission(l, radius, &em);
      omega = em.omega;
      scale = em.scale;
      e->cos_max = em.cos_max;
    }
    if (!world) memcpy(col, l->color, sizeof col);
    k = scale / counts[i];
    for (int c = 0; c < 3; ++c) e->power[c] = (float)(col[c] * (world ? 1.0 : (double)l->intensity) * k);
    e->diff_scale = (float)(sqrt(omega / counts[i]) / delta);
  }
  t->p.scene_center[0] = center[0];
  t->p.scene_center[1] = center[1];
  t->p.scene_center[2] = center[2];
  t->p.scene_radius = radius;
  t->p.photons = total; /* == d->photons when any light has power */
  t->p.light_count = t->light_entries;
  t->p.delta = delta;
  t->p.r_max = d->r_max > 0.0f ? d->r_max : PB_PHOTON_R_MAX_FACTOR * delta * radius; /* photon.h */
  /* Seed 003 section 6: h = C sqrt(A / N), C = C0 / sqrt(p), A the scene's
   * total area, N the photons emitted (this iteration's paths: each map is
   * an estimate of its own); the 1 / sqrt(p) factor per photon in
   * pb_store. The pose changes A (moving, deforming objects). */
  t->p.bandwidth_h0 = 0.0f;
  if (d->bandwidth_c0 > 0.0f && total > 0) {
    t->p.bandwidth_h0 = (float)(d->bandwidth_c0 * sqrt(surface_area(s) / (double)total));
    t->p.bandwidth_p_min = PB_PHOTON_BANDWIDTH_P_MIN;
    t->p.bandwidth_p_max = PB_PHOTON_BANDWIDTH_P_MAX;
  }
  t->stats.photons = total;
  t->stats.delta = delta;
  t->stats.r_max = t->p.r_max;
  t->stats.scene_radius = radius;
  *radius_out = radius;
}

pb_result pb_photon_tracer_update(pb_gpu *g, pb_photon_tracer *t, const pb_scene *s) {
  uint32_t slots = pb_photon_slots(s) ? pb_photon_slots(s) : 1;
  uint32_t *counts = calloc(slots, sizeof *counts);
  uint32_t *firsts = calloc(slots, sizeof *firsts);
  pb_result r = PB_OK;
  if (!counts || !firsts) {
    r = pb_fail(PB_ERR_NOMEM, "photons: out of memory");
    goto done;
  }
  float center[3], radius;
  scene_lights(t, s, counts, firsts, center, &radius);
  if (t->rsm) {
    /* The reflective shadow maps follow the lights and the geometry: made
     * again for the new pose and rendered by the next run. */
    pb_photon_rsm_destroy(g, t->rsm);
    t->rsm = NULL;
    t->rsm_ready = 0;
    for (uint32_t i = 0; i < t->light_entries; ++i) counts[i] = t->lights[i].light;
    r = pb_photon_rsm_create(g, s, t->gs, counts, t->light_entries, t->desc.rsm_resolution, center, radius,
                             t->desc.caustic_share, &t->rsm);
  }
done:
  free(counts);
  free(firsts);
  return r;
}

pb_result pb_photon_tracer_create(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs,
                                  const pb_photon_trace_desc *desc, pb_photon_tracer **out) {
  *out = NULL;
  pb_photon_trace_desc d = desc ? *desc : (pb_photon_trace_desc){0};
  if (!d.photons) d.photons = 1u << 18;
  /* Unbounded by default (photon.h, PB_PHOTON_BOUNCE_CAP): Russian roulette
   * ends the paths, as in the reference. 7 stored bounces (the old default,
   * 8 scattering events with the unstored direct hit) lost rho^8 of a closed
   * room's indirect light (10 % at albedo 0.75); 3 truncated more
   * (cornell_box 128 px, 8 maps of 2^16: 26.8 dB against the reference with
   * 3, 29.7 dB with 7). bench/README.md, "Path length", has the cost. */
  if (!d.max_bounces) d.max_bounces = PB_PHOTON_BOUNCE_CAP;
  if (d.smoothing == 0.0f) d.smoothing = PB_PHOTON_SMOOTHING_DEFAULT;
  if (d.smoothing_caustic == 0.0f) d.smoothing_caustic = PB_PHOTON_SMOOTHING_CAUSTIC_DEFAULT;
  if (d.max_bounces > 255)
    return pb_fail(PB_ERR_USAGE, "photons: max_bounces %u (at most 255)", d.max_bounces);
  if (!(d.smoothing > 0.0f) || !(d.smoothing_caustic > 0.0f) || !isfinite(d.smoothing) ||
      !isfinite(d.smoothing_caustic))
    return pb_fail(PB_ERR_USAGE, "photons: smoothing factors must be positive (%g, %g)", d.smoothing,
                   d.smoothing_caustic);
  if (d.first_bounce > PB_FIRST_BOUNCE_AUTO)
    return pb_fail(PB_ERR_USAGE, "photons: first_bounce %u (TRACE, RSM or AUTO)", d.first_bounce);
  if (!d.rsm_resolution) d.rsm_resolution = 64;
  if (d.caustic_share == 0.0f) d.caustic_share = PB_PHOTON_CAUSTIC_SHARE_DEFAULT;
  if (d.caustic_share < 0.0f) d.caustic_share = 0.0f; /* off: by reflected power */
  if (!(d.caustic_share < 1.0f))
    return pb_fail(PB_ERR_USAGE, "photons: caustic share %g (in [0, 1))", d.caustic_share);
  if (d.r_max < 0.0f || !isfinite(d.r_max))
    return pb_fail(PB_ERR_USAGE, "photons: r_max %g must be positive", d.r_max);
  if (d.bandwidth_c0 < 0.0f || !isfinite(d.bandwidth_c0))
    return pb_fail(PB_ERR_USAGE, "photons: bandwidth C0 %g must be positive", d.bandwidth_c0);
  /* 3-D dispatch fold limit: gid is a uint. */
  if (d.photons > 0x7fffffffu) return pb_fail(PB_ERR_LIMIT, "photons: %u paths (at most 2^31 - 1)", d.photons);
  uint64_t capacity = (uint64_t)d.photons *
                      (d.max_bounces < PB_PHOTON_RECORDS_PER_PATH ? d.max_bounces : PB_PHOTON_RECORDS_PER_PATH);
  const pb_gpu_limits *lim = pb_gpu_get_limits(g);
  uint64_t device_max = lim->max_storage_buffer_range / sizeof(pb_gpu_photon);
  if (device_max > 0xffffffffu) device_max = 0xffffffffu;
  if (capacity > device_max) capacity = device_max;
  if (capacity < d.photons)
    return pb_fail(PB_ERR_LIMIT,
                   "photons: %u paths need at least %u photon records (%llu bytes), over the device's "
                   "maxStorageBufferRange of %llu bytes; lower the photon budget",
                   d.photons, d.photons, (unsigned long long)d.photons * sizeof(pb_gpu_photon),
                   (unsigned long long)lim->max_storage_buffer_range);

  pb_photon_tracer *t = calloc(1, sizeof *t);
  if (!t) return pb_fail(PB_ERR_NOMEM, "photons: out of memory");
  pb_result r = PB_OK;
  uint32_t slots = pb_photon_slots(s) ? pb_photon_slots(s) : 1;
  uint32_t *counts = calloc(slots, sizeof *counts);
  uint32_t *firsts = calloc(slots, sizeof *firsts);
  t->lights = calloc(slots, sizeof *t->lights);
  if (!counts || !firsts || !t->lights) {
    r = pb_fail(PB_ERR_NOMEM, "photons: out of memory");
    goto fail;
  }
  t->gs = gs;
  t->desc = d;
  float center[3], radius;
  scene_lights(t, s, counts, firsts, center, &radius);
  t->p.max_bounces = d.max_bounces;
  t->p.max_depth = d.max_bounces + 1 + PB_PHOTON_MAX_SPECULAR;
  t->p.capacity = (uint32_t)capacity;
  t->p.smoothing = d.smoothing;
  t->p.smoothing_caustic = d.smoothing_caustic;
  t->p.flags |= PB_PHOTON_PARAM_CAUSTIC_RAW; /* caustic footprints uncompressed (photon.h) */
  if (d.first_bounce == PB_FIRST_BOUNCE_RSM || d.first_bounce == PB_FIRST_BOUNCE_AUTO) {
    for (uint32_t i = 0; i < t->light_entries; ++i) counts[i] = t->lights[i].light;
    if ((r = pb_photon_rsm_create(g, s, gs, counts, t->light_entries, d.rsm_resolution, center, radius,
                                  d.caustic_share, &t->rsm)) != PB_OK)
      goto fail;
    t->p.flags |= PB_PHOTON_PARAM_RSM;
    if (d.first_bounce == PB_FIRST_BOUNCE_AUTO) t->p.flags |= PB_PHOTON_PARAM_RSM_AUTO;
  }

  pb_gpu_buffer_desc fd = {.name = "photons.frame", .size = sizeof(pb_gpu_frame), .host_visible = 1};
  if ((r = pb_gpu_buffer_create(g, &fd, &t->frame)) != PB_OK) goto fail;
  uint32_t entries = slots; /* room for every light and the world: poses may change the split */
  pb_gpu_buffer_desc pd = {.name = "photons.params",
                           .size = sizeof(pb_gpu_photon_params) + entries * sizeof(pb_gpu_photon_light),
                           .host_visible = 1};
  if ((r = pb_gpu_buffer_create(g, &pd, &t->params)) != PB_OK) goto fail;

  pb_render_plan plan;
  pb_render_plan_of(s, 0, &plan);
  t->spec[PB_SPEC_HAS_NORMALS] = plan.vertex_normals ? 1u : 0u;
  t->spec[PB_SPEC_TEXTURES] = plan.textures ? 1u : 0u;
  t->spec[PB_SPEC_SPECULAR] = plan.caustic_photons ? 1u : 0u;
  t->spec[PB_SPEC_EMISSIVE] = emitter_slot(s) ? 1u : 0u; /* photons start at emissive triangles too (pb_emission) */
  t->spec[PB_SPEC_TRANSMISSION] = plan.refraction ? 1u : 0u;
  t->spec[PB_SPEC_SOFT_LIGHTS] = plan.soft_lights ? 1u : 0u;
  t->spec[PB_SPEC_WORLD] = plan.world ? 1u : 0u;
  t->spec[PB_SPEC_ALPHA] = plan.alpha ? 1u : 0u;
  t->spec[PB_SPEC_PRINCIPLED2] = plan.principled2 ? 1u : 0u;
  t->spec[PB_SPEC_CLOSURES] = plan.closures;
  static const pb_kernel_builds k = PB_KERNEL_BUILDS(photon_trace);
  pb_gpu_pipeline_desc pdsc = {
      .name = "pass.photon_trace",
      .binding_count = PB_PHOTON_BIND_COUNT,
      .push_bytes = 0,
      .spec = t->spec,
      .spec_count = PB_SPEC_COUNT,
  };
  pb_kernel_select(&pdsc, &k, plan.blender_materials, gs->ray_query, PB_BIND_NODES);
  t->blender = plan.blender_materials ? 1 : 0;
  if ((r = pb_gpu_pipeline_create(g, &pdsc, &t->pipe)) != PB_OK) goto fail;
  free(counts);
  free(firsts);
  *out = t;
  return PB_OK;
fail:
  free(counts);
  free(firsts);
  pb_photon_tracer_destroy(g, t);
  return r;
}

static pb_result map_create(pb_gpu *g, const pb_photon_tracer *t, pb_photon_map *m) {
  memset(m, 0, sizeof *m);
  m->capacity = t->p.capacity;
  pb_gpu_buffer_desc pd = {.name = "photons.map",
                           .size = (uint64_t)(m->capacity ? m->capacity : 1) * sizeof(pb_gpu_photon)};
  pb_result r = pb_gpu_buffer_create(g, &pd, &m->photons);
  if (r != PB_OK) return r;
  pb_gpu_buffer_desc cd = {.name = "photons.counts", .size = sizeof(pb_gpu_photon_counts), .host_visible = 1};
  if ((r = pb_gpu_buffer_create(g, &cd, &m->counts)) != PB_OK) pb_photon_map_destroy(g, m);
  return r;
}

pb_result pb_photon_tracer_prepare(pb_gpu *g, pb_photon_tracer *t, uint64_t seed, uint32_t iteration,
                                   pb_photon_map *map) {
  pb_result r;
  if (!map->photons.buffer) {
    if ((r = map_create(g, t, map)) != PB_OK) return r;
  } else if (map->capacity != t->p.capacity) {
    return pb_fail(PB_ERR_INTERNAL, "photons: map of capacity %u reused with a tracer of capacity %u",
                   map->capacity, t->p.capacity);
  }
  const pb_gpu_scene *gs = t->gs;
  const pb_gpu_buffer *b[PB_PHOTON_IMAGES_BIND_COUNT] = {
      [PB_BIND_FRAME] = &t->frame, [PB_BIND_NODES] = &gs->nodes, [PB_BIND_TRIS] = &gs->tris,
      [PB_BIND_INDICES] = &gs->indices, [PB_BIND_NORMALS] = &gs->normals, [PB_BIND_UVS] = &gs->uvs,
      [PB_BIND_TRI_MATERIAL] = &gs->tri_material, [PB_BIND_MATERIALS] = &gs->materials,
      [PB_BIND_TEXTURES] = &gs->textures, [PB_BIND_TEXELS] = &gs->texels, [PB_BIND_LIGHTS] = &gs->lights,
      [PB_PHOTON_BIND_PHOTONS] = &map->photons, [PB_PHOTON_BIND_COUNTS] = &map->counts,
      [PB_BIND_POSITIONS] = &gs->positions, [PB_BIND_EMITTERS] = &gs->emitters, [PB_PHOTON_BIND_PARAMS] = &t->params,
      /* TRACE: never read, any buffer will do */
      [PB_PHOTON_BIND_RSM_LIGHTS] = t->rsm ? pb_photon_rsm_lights(t->rsm) : &t->params,
      [PB_PHOTON_BIND_RSM_TEXELS] = t->rsm ? pb_photon_rsm_texels(t->rsm) : &t->params,
      [PB_PHOTON_BIND_WORLD] = &gs->world,
      [PB_PHOTON_BIND_IMAGE_MAPS] = t->images ? pb_image_maps_buffer(t->images) : &t->params,
      [PB_PHOTON_BIND_IMAGE_TEXELS] = t->images ? pb_image_maps_texels(t->images) : &t->params,
      [PB_PHOTON_BIND_IMAGE_COUNTS] = t->images ? &t->image_counts : &t->params};
  uint32_t nb = t->images ? PB_PHOTON_IMAGES_BIND_COUNT : PB_PHOTON_BIND_COUNT;
  if ((r = pb_kernel_bind(g, &t->pipe, b, nb, pb_gpu_scene_accel(gs))) != PB_OK) return r;
  if (t->images && (r = pb_gpu_buffer_fill_zero(g, &t->image_counts)) != PB_OK) return r;
  if (t->rsm && (r = pb_photon_rsm_bind(g, t->rsm, &t->frame)) != PB_OK) return r;

  pb_gpu_frame fr;
  memset(&fr, 0, sizeof fr);
  fr.seed_lo = (uint32_t)seed;
  fr.seed_hi = (uint32_t)(seed >> 32);
  fr.light_count = gs->light_count;
  fr.uv1_base = gs->uv1_base; /* base colours of photon bounces */
  fr.color_base = gs->color_base;
  fr.principled2_base = gs->principled2_base; /* v2 materials at bounces */
  if ((r = pb_gpu_buffer_upload(g, &t->frame, 0, &fr, sizeof fr)) != PB_OK) return r;
  t->p.iteration = iteration;
  t->p.guarded = t->p.absorbed = t->p.escaped = 0;
  if ((r = pb_gpu_buffer_upload(g, &t->params, 0, &t->p, sizeof t->p)) != PB_OK) return r;
  if (t->light_entries &&
      (r = pb_gpu_buffer_upload(g, &t->params, sizeof t->p, t->lights,
                                (uint64_t)t->light_entries * sizeof *t->lights)) != PB_OK)
    return r;
  pb_gpu_photon_counts zero = {0};
  return pb_gpu_buffer_upload(g, &map->counts, 0, &zero, sizeof zero);
}

pb_result pb_photon_tracer_record(pb_gpu *g, pb_photon_tracer *t, uint32_t ts_slot) {
  pb_result r;
  pb_gpu_timestamp(g, ts_slot);
  if (t->rsm && !t->rsm_ready && (r = pb_photon_rsm_record(g, t->rsm)) != PB_OK) return r;
  if ((r = pb_gpu_dispatch(g, &t->pipe, NULL, t->p.photons)) != PB_OK) return r;
  pb_gpu_timestamp(g, ts_slot + 1);
  if (t->rsm) t->rsm_ready = 1;
  return PB_OK;
}

pb_result pb_photon_tracer_run(pb_gpu *g, pb_photon_tracer *t, uint64_t seed, uint32_t iteration,
                               pb_photon_map *map, double *gpu_ms) {
  pb_result r = pb_photon_tracer_prepare(g, t, seed, iteration, map);
  if (r != PB_OK) return r;
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  r = pb_photon_tracer_record(g, t, 0);
  pb_result rs = pb_gpu_submit(g); /* ends the recording; a recording error is the one to report */
  if (r == PB_OK) r = rs;
  if (r != PB_OK) return r;
  return pb_photon_tracer_finish(g, t, map, 0, gpu_ms);
}

pb_result pb_photon_tracer_finish(pb_gpu *g, pb_photon_tracer *t, pb_photon_map *map, uint32_t ts_slot,
                                  double *gpu_ms) {
  pb_result r;
  if (gpu_ms) *gpu_ms = pb_gpu_elapsed_ms(g, ts_slot, ts_slot + 1);
  pb_gpu_photon_counts c;
  if ((r = pb_gpu_buffer_download(g, &map->counts, 0, &c, sizeof c)) != PB_OK) return r;
  map->stored = c.stored;
  map->caustic = c.caustic;
  map->emitted = c.emitted;
  map->overflow = c.overflow;
  map->clamped = c.clamped;
  pb_gpu_photon_params pp;
  if ((r = pb_gpu_buffer_download(g, &t->params, 0, &pp, sizeof pp)) != PB_OK) return r;
  t->stats.guarded = pp.guarded;
  t->stats.absorbed = pp.absorbed;
  t->stats.escaped = pp.escaped;
  t->stats.rsm_lights = 0;
  t->stats.rsm_coverage = 1.0f;
  if (t->rsm && (r = pb_photon_rsm_coverage(g, t->rsm, (t->p.flags & PB_PHOTON_PARAM_RSM_AUTO) != 0,
                                            &t->stats.rsm_lights, &t->stats.rsm_coverage)) != PB_OK)
    return r;
  t->stats.rsm_boost = 1.0f;
  if (t->rsm && (r = pb_photon_rsm_boost(g, t->rsm, &t->stats.rsm_boost)) != PB_OK) return r;
  if (t->rsm && t->stats.rsm_boost > 1.0f)
    pb_log_verbose("photons: specular RSM texels weighted x %.3g (caustic share %g)", (double)t->stats.rsm_boost,
                   (double)t->desc.caustic_share);
  if (t->images &&
      (r = pb_gpu_buffer_download(g, &t->image_counts, 0, &t->image_last, sizeof t->image_last)) != PB_OK)
    return r;
  if (c.stored > map->capacity)
    return pb_fail(PB_ERR_INTERNAL, "photons: %u stored in a map of %u", c.stored, map->capacity);
  if (c.overflow)
    return pb_fail(PB_ERR_LIMIT,
                   "photons: the map needed %llu photon records, the device's storage buffers hold %u "
                   "(maxStorageBufferRange); lower --photons or --photon-bounces",
                   (unsigned long long)c.stored + c.overflow, map->capacity);
  return PB_OK;
}

void pb_photon_tracer_stats(const pb_photon_tracer *t, pb_photon_trace_stats *out) {
  memset(out, 0, sizeof *out);
  if (t) *out = t->stats;
}

void pb_photon_tracer_debug(pb_photon_tracer *t, float h, uint32_t depth, uint32_t flags) {
  t->p.stencil_h = h > 0.0f ? h : 0.0f;
  t->p.stencil_depth = depth;
  t->p.flags = (flags & (PB_PHOTON_PARAM_RAW_FOOTPRINT | PB_PHOTON_PARAM_STORE_FIRST)) |
               (t->p.flags & (PB_PHOTON_PARAM_RSM | PB_PHOTON_PARAM_RSM_AUTO | PB_PHOTON_PARAM_CAUSTIC_RAW));
}

pb_result pb_photon_tracer_use_image_maps(pb_gpu *g, pb_photon_tracer *t, const pb_image_maps *maps) {
  pb_gpu_pipeline_desc pdsc = {
      .name = "pass.photon_trace_images",
      .spirv = t->blender ? pb_spv_photon_trace_images_blender : pb_spv_photon_trace_images,
      .spirv_bytes = t->blender ? sizeof pb_spv_photon_trace_images_blender : sizeof pb_spv_photon_trace_images,
      .binding_count = PB_PHOTON_IMAGES_BIND_COUNT,
      .spec = t->spec,
      .spec_count = PB_SPEC_COUNT,
  };
  pb_gpu_pipeline pipe;
  pb_result r = pb_gpu_pipeline_create(g, &pdsc, &pipe);
  if (r != PB_OK) return r;
  if (!t->image_counts.buffer) {
    pb_gpu_buffer_desc cd = {.name = "photons.image_counts", .size = sizeof(pb_gpu_image_counts), .readback = 1};
    if ((r = pb_gpu_buffer_create(g, &cd, &t->image_counts)) != PB_OK) {
      pb_gpu_pipeline_destroy(g, &pipe);
      return r;
    }
  }
  pb_gpu_pipeline_destroy(g, &t->pipe);
  t->pipe = pipe;
  t->images = maps;
  return PB_OK;
}

void pb_photon_tracer_image_counts(const pb_photon_tracer *t, pb_gpu_image_counts *out) {
  memset(out, 0, sizeof *out);
  if (t && t->images) *out = t->image_last;
}

void pb_photon_tracer_destroy(pb_gpu *g, pb_photon_tracer *t) {
  if (!t) return;
  pb_gpu_buffer_destroy(g, &t->image_counts);
  pb_photon_rsm_destroy(g, t->rsm);
  pb_gpu_pipeline_destroy(g, &t->pipe);
  pb_gpu_buffer_destroy(g, &t->params);
  pb_gpu_buffer_destroy(g, &t->frame);
  free(t->lights);
  free(t);
}

void pb_photon_map_destroy(pb_gpu *g, pb_photon_map *m) {
  if (!m) return;
  pb_gpu_buffer_destroy(g, &m->photons);
  pb_gpu_buffer_destroy(g, &m->counts);
  memset(m, 0, sizeof *m);
}
