/* The view-sample cluster hierarchy estimator (seed 004, Moreau et al. 2016,
 * "Photon Splatting Using a View-Sample Cluster Hierarchy"), behind the
 * estimator interface (estimator.h). Per sample, after the G-buffer pass,
 * one stretch of dispatches with no host round trip (shaders/vsch_*.comp;
 * the layout in shaders/shared/pb_vsch.h):
 *   hierarchy (4.1, 4.5)  clear, range (depth range, photon irradiance
 *                         range), mark (grid cells, tile masks), scan (the
 *                         compact cluster list), leaf (boxes, normal sums),
 *                         cone (cluster cones), up x PB_VSCH_LEVELS (masks,
 *                         boxes and cones propagated up);
 *   splat (4.3, 4.5-4.7)  count (one invocation per photon traverses the
 *                         hierarchy: list insertions counted, trivially
 *                         accepted and directional flux added to the nodes),
 *                         scan (prefix sum over the photons), fill ((node,
 *                         photon) pairs), a stable radix sort of the pairs by
 *                         node (lbvh_sort.c), ranges (each node's list);
 *   estimate (4.4, 4.7)   shade (L = sum f Phi / (pi r^2) over the lists of
 *                         the nodes holding the sample, plus the nodes'
 *                         trivial flux) into the frame's pb_gpu_photon_accum;
 *                         directional: blur (the octant irradiance, blurred
 *                         by depth and normal, times f).
 * Count, prefix sum and fill rather than atomics into the per-pixel
 * accumulator: a photon's contribution needs the BSDF of each sample, which
 * the per-sample shading pass evaluates once per (sample, photon) from the
 * lists, and the pairs in photon order, sorted stably, keep each list in
 * the same order every run (vsch_count.comp): the image is the same bit for
 * bit for a fixed seed.
 * The hierarchy is rebuilt for every sample (the G-buffer changes with the
 * pixel jitter); the photon map's count is read on the GPU. Nothing is
 * built per map (record_build records nothing). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "render/estimate/estimator.h"
#include "render/photon/lbvh_sort.h"
#include "render/scene/passes.h"
#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_photon.h"
#include "shared/pb_vsch.h"
#include "shaders/vsch_blur.spv.h"
#include "shaders/vsch_clear.spv.h"
#include "shaders/vsch_cone.spv.h"
#include "shaders/vsch_count.spv.h"
#include "shaders/vsch_fill.spv.h"
#include "shaders/vsch_leaf.spv.h"
#include "shaders/vsch_mark.spv.h"
#include "shaders/vsch_range.spv.h"
#include "shaders/vsch_ranges.spv.h"
#include "shaders/vsch_scan.spv.h"
#include "shaders/vsch_shade.spv.h"
#include "shaders/vsch_shade_blender.spv.h"
#include "shaders/vsch_shade_rq.spv.h"
#include "shaders/vsch_shade_rq_blender.spv.h"
#include "shaders/vsch_leaf_rq.spv.h"
#include "shaders/vsch_up.spv.h"

enum { P_CLEAR = 0, P_RANGE, P_MARK, P_SCAN, P_CONE, P_UP, P_COUNT, P_FILL, P_RANGES, P_N };

typedef struct vsch {
  pb_estimator_desc desc;
  pb_gpu_pipeline pass[P_N];
  pb_gpu_pipeline leaf, shade, blur;
  uint32_t shade_spec[PB_SPEC_COUNT];
  uint32_t shade_build; /* pb_kernel_select's */
  int have_shade, bound;
  pb_radix_sort *sort;
  uint32_t sort_bits;
  pb_gpu_buffer data, dummy;
  uint32_t pixel_cap, photon_cap, pair_cap, node_count, directional_cap;
  pb_gpu_vsch_push push; /* the layout; per record: sample, flags, pixels */
  /* The map of the iteration (begin_map). */
  pb_gpu_buffer photons, counts;
  uint32_t capacity, stored;
  float footprint_scale;
  uint32_t pairs_wanted; /* the most (node, photon) pairs a sample wanted so far */
  int warned;
} vsch;

static void free_buffers(pb_gpu *g, vsch *v) {
  pb_gpu_buffer_destroy(g, &v->data);
  v->pixel_cap = v->photon_cap = v->pair_cap = v->node_count = 0;
  v->bound = 0;
}

static void vsch_destroy(pb_gpu *g, void *impl) {
  vsch *v = impl;
  if (!v) return;
  for (int i = 0; i < P_N; ++i) pb_gpu_pipeline_destroy(g, &v->pass[i]);
  pb_gpu_pipeline_destroy(g, &v->leaf);
  pb_gpu_pipeline_destroy(g, &v->shade);
  pb_gpu_pipeline_destroy(g, &v->blur);
  free_buffers(g, v);
  pb_radix_sort_destroy(g, v->sort);
  pb_gpu_buffer_destroy(g, &v->dummy);
  free(v);
}

static pb_result vsch_create(pb_gpu *g, const pb_scene *s, const pb_estimator_desc *desc, void **impl) {
  (void)s;
  *impl = NULL;
  if (desc && !(desc->vsch.radius >= 0.0f && isfinite(desc->vsch.radius)))
    return pb_fail(PB_ERR_USAGE, "vsch estimator: photon radius %g (a length in metres >= 0; 0: each photon's own)",
                   (double)desc->vsch.radius);
  vsch *v = calloc(1, sizeof *v);
  if (!v) return pb_fail(PB_ERR_NOMEM, "vsch estimator: out of memory");
  if (desc) v->desc = *desc;
  static const struct {
    const char *name;
    const uint32_t *spv;
    size_t bytes;
  } k[P_N] = {
      {"vsch.clear", pb_spv_vsch_clear, sizeof pb_spv_vsch_clear},
      {"vsch.range", pb_spv_vsch_range, sizeof pb_spv_vsch_range},
      {"vsch.mark", pb_spv_vsch_mark, sizeof pb_spv_vsch_mark},
      {"vsch.scan", pb_spv_vsch_scan, sizeof pb_spv_vsch_scan},
      {"vsch.cone", pb_spv_vsch_cone, sizeof pb_spv_vsch_cone},
      {"vsch.up", pb_spv_vsch_up, sizeof pb_spv_vsch_up},
      {"vsch.count", pb_spv_vsch_count, sizeof pb_spv_vsch_count},
      {"vsch.fill", pb_spv_vsch_fill, sizeof pb_spv_vsch_fill},
      {"vsch.ranges", pb_spv_vsch_ranges, sizeof pb_spv_vsch_ranges},
  };
  pb_result r = PB_OK;
  for (int i = 0; i < P_N && r == PB_OK; ++i) {
    pb_gpu_pipeline_desc pd = {.name = k[i].name, .spirv = k[i].spv, .spirv_bytes = k[i].bytes,
                               .binding_count = PB_VSCH_BIND_COUNT, .push_bytes = sizeof(pb_gpu_vsch_push)};
    r = pb_gpu_pipeline_create(g, &pd, &v->pass[i]);
  }
  pb_gpu_buffer_desc dd = {.name = "vsch.dummy", .size = 256};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &dd, &v->dummy);
  if (r != PB_OK) {
    vsch_destroy(g, v);
    return r;
  }
  *impl = v;
  return PB_OK;
}

static void vsch_update(void *impl, const pb_scene *s) {
  (void)impl;
  (void)s; /* the hierarchy is rebuilt from the G-buffer every sample */
}

static pb_result vsch_begin_map(pb_gpu *g, void *impl, const pb_photon_map *map, const pb_estimator_map_info *info) {
  (void)g;
  vsch *v = impl;
  v->photons = map->photons;
  v->counts = map->counts;
  v->capacity = map->photons.buffer ? map->capacity : 0;
  v->stored = map->stored;
  v->footprint_scale = info && info->footprint_scale > 0.0f && isfinite(info->footprint_scale) ? info->footprint_scale
                                                                                                 : 1.0f;
  v->bound = 0;
  return PB_OK;
}

static pb_result vsch_record_build(pb_gpu *g, void *impl, uint32_t ts_slot) {
  (void)g, (void)impl, (void)ts_slot;
  return PB_OK;
}

static void vsch_build_done(pb_gpu *g, void *impl, uint32_t ts_slot, double *gpu_ms) {
  (void)g, (void)impl, (void)ts_slot;
  if (gpu_ms) *gpu_ms = 0.0; /* nothing built per map: the hierarchy is part of every sample's record */
}

static uint32_t bits_for(uint64_t n) {
  uint32_t b = 1;
  while (b < 32 && (1ull << b) < n) ++b;
  return b;
}

/* The data buffer for bands of up to `pixels` pixels and maps of `cap`
 * records. Levels: the clusters of a band are at most one per sample; its
 * tiles at most pixels / 8 + 1 for any width (ceil(W/8) ceil(H/8) <=
 * (W H + 7 (W + H) + 49) / 64 with W + H <= W H + 1); a level above at most
 * half the one below, or 1 (ceil(a/8) ceil(b/4) <= max(1, a b / 2)). */
static pb_result reserve(pb_gpu *g, vsch *v, uint32_t pixels, uint32_t cap) {
  if (pixels == 0) pixels = 1;
  uint32_t directional = v->desc.vsch.directional ? 1u : 0u;
  /* The pairs' capacity (the sort's): 4 per pixel and per photon record,
   * at least 2^16, grown to 1.5 x the most a sample wanted (read back at
   * every bind: the next map has room). A sample that wants more drops the
   * rest, counted (pairs_dropped) and warned about once. */
  uint64_t want = 4ull * pixels + 4ull * cap;
  if (want < 65536u) want = 65536u;
  if (want < v->pairs_wanted + v->pairs_wanted / 2ull) want = v->pairs_wanted + v->pairs_wanted / 2ull;
  if (want > 0x3fffffffull) want = 0x3fffffffull;
  uint32_t pair_cap = (uint32_t)want;
  if (v->data.buffer && pixels <= v->pixel_cap && cap <= v->photon_cap && pair_cap <= v->pair_cap &&
      directional <= v->directional_cap)
    return PB_OK;
  free_buffers(g, v);
  pb_gpu_vsch_push p;
  memset(&p, 0, sizeof p);
  uint64_t base = pixels, level = pixels / 8u + 1u;
  p.level_base[0] = 0;
  for (uint32_t L = 1; L <= PB_VSCH_LEVELS; ++L) {
    p.level_base[L] = (uint32_t)base;
    base += level;
    level = level / 2u + 1u;
  }
  uint64_t nodes = base;
  uint64_t w = PB_VSCH_HEADER_WORDS;
  p.node_off = (uint32_t)w, w += nodes * PB_VSCH_NODE_WORDS;
  p.triv_off = (uint32_t)w, w += nodes * PB_VSCH_TRIVIAL_WORDS;
  if (directional) p.dir_off = (uint32_t)w, w += nodes * PB_VSCH_DIR_WORDS;
  p.pixel_off = (uint32_t)w, w += (uint64_t)pixels * PB_VSCH_PIXEL_WORDS;
  p.photon_off = (uint32_t)w, w += 2ull * (cap ? cap : 1u);
  if (w > 0xffffffffull / 4u)
    return pb_fail(PB_ERR_LIMIT, "vsch estimator: %u pixels and %u photon records need %llu words of hierarchy data, "
                   "over 2^30; render fewer pixels or photons", pixels, cap, (unsigned long long)w);
  p.nodes = (uint32_t)nodes;
  p.pair_cap = pair_cap;
  p.max_groups_x = pb_gpu_get_limits(g)->max_workgroup_count_x;
  pb_gpu_buffer_desc dd = {.name = "vsch.data", .size = w * 4u}; /* device memory: stats() downloads the header */
  pb_result r = pb_gpu_buffer_create(g, &dd, &v->data);
  if (r != PB_OK) return r;
  uint32_t bits = bits_for(nodes);
  if (!v->sort || bits != v->sort_bits) {
    pb_radix_sort_destroy(g, v->sort);
    v->sort = NULL;
    pb_radix_sort_desc sd = {.key_bits = bits};
    if ((r = pb_radix_sort_create(g, &sd, &v->sort)) != PB_OK) goto fail;
    v->sort_bits = bits;
  }
  if ((r = pb_radix_sort_reserve(g, v->sort, pair_cap)) != PB_OK) goto fail;
  if ((r = pb_radix_sort_bind(g, v->sort, &v->data, PB_VSCH_H_PAIRS)) != PB_OK) goto fail;
  p.sorted = pb_radix_sort_result(v->sort);
  v->push = p;
  v->pixel_cap = pixels, v->photon_cap = cap, v->pair_cap = pair_cap, v->node_count = (uint32_t)nodes;
  v->directional_cap = directional;
  return PB_OK;
fail:
  free_buffers(g, v);
  return r;
}

static pb_result vsch_bind(pb_gpu *g, void *impl, const struct pb_pass_setup *ps, const pb_gpu_buffer *photon_accum,
                           const pb_gpu_buffer *photon_nmap) {
  vsch *v = impl;
  pb_result r;
  uint32_t pixels = (uint32_t)(photon_accum->size / sizeof(pb_gpu_photon_accum));
  if (v->data.buffer) { /* the last sample's wanted pairs */
    uint32_t listed = 0;
    if ((r = pb_gpu_buffer_download(g, &v->data, PB_VSCH_H_LISTED * 4u, &listed, 4)) != PB_OK) return r;
    if (listed > v->pairs_wanted) v->pairs_wanted = listed;
  }
  if ((r = reserve(g, v, pixels, v->capacity)) != PB_OK) return r;
  uint32_t spec[PB_SPEC_COUNT] = {0};
  memcpy(spec, ps->spec, PB_SPEC_SHADING_COUNT * sizeof *spec); /* scene.glsl's 0-5, as the gather */
  spec[PB_SPEC_NORMAL_MAPS] = ps->normal_maps ? 1u : 0u;
  /* The leaf and shade kernels trace (their kernel-edge and visibility
   * rays); the blur does not. */
  static const pb_kernel_builds kleaf = PB_KERNEL_BUILDS_GLTF(vsch_leaf), kshade = PB_KERNEL_BUILDS(vsch_shade);
  pb_gpu_pipeline_desc d[3] = {
      {.name = "vsch.leaf"},
      {.name = "vsch.shade"},
      {.name = "vsch.blur", .spirv = pb_spv_vsch_blur, .spirv_bytes = sizeof pb_spv_vsch_blur},
  };
  pb_kernel_select(&d[0], &kleaf, ps->blender, ps->accel != NULL, PB_BIND_NODES);
  uint32_t build = pb_kernel_select(&d[1], &kshade, ps->blender, ps->accel != NULL, PB_BIND_NODES);
  if (v->have_shade && (memcmp(v->shade_spec, spec, sizeof spec) != 0 || v->shade_build != build)) {
    pb_gpu_pipeline_destroy(g, &v->leaf);
    pb_gpu_pipeline_destroy(g, &v->shade);
    pb_gpu_pipeline_destroy(g, &v->blur);
    v->have_shade = 0;
  }
  if (!v->have_shade) {
    pb_gpu_pipeline *out[3] = {&v->leaf, &v->shade, &v->blur};
    for (int i = 0; i < 3; ++i) {
      d[i].binding_count = PB_VSCH_SHADE_BIND_COUNT;
      d[i].push_bytes = sizeof(pb_gpu_vsch_push);
      d[i].spec = spec;
      d[i].spec_count = PB_SPEC_COUNT;
      if ((r = pb_gpu_pipeline_create(g, &d[i], out[i])) != PB_OK) return r;
    }
    memcpy(v->shade_spec, spec, sizeof spec);
    v->shade_build = build;
    v->have_shade = 1;
  }
  const pb_gpu_buffer *photons = v->photons.buffer ? &v->photons : &v->dummy;
  const pb_gpu_buffer *a[PB_VSCH_BIND_COUNT] = {
      [PB_VSCH_BIND_FRAME] = ps->bindings[PB_BIND_FRAME], [PB_VSCH_BIND_GBUFFER] = ps->bindings[PB_BIND_GBUFFER],
      [PB_VSCH_BIND_DATA] = &v->data, [PB_VSCH_BIND_PHOTONS] = photons,
      [PB_VSCH_BIND_COUNTS] = v->counts.buffer ? &v->counts : &v->dummy,
      [PB_VSCH_BIND_KEYS] = pb_radix_sort_keys(v->sort), [PB_VSCH_BIND_VALS] = pb_radix_sort_vals(v->sort)};
  for (int i = 0; i < P_N; ++i)
    if ((r = pb_gpu_pipeline_bind(g, &v->pass[i], a, PB_VSCH_BIND_COUNT)) != PB_OK) return r;
  const pb_gpu_buffer *b[PB_VSCH_SHADE_BIND_COUNT];
  for (int i = 0; i < PB_BIND_WORLD; ++i) b[i] = ps->bindings[i]; /* the scene's 15 */
  b[PB_VSCH_SHADE_BIND_DATA] = &v->data;
  b[PB_VSCH_SHADE_BIND_PHOTONS] = photons;
  b[PB_VSCH_SHADE_BIND_VALS] = pb_radix_sort_vals(v->sort);
  b[PB_VSCH_SHADE_BIND_ACCUM] = photon_accum;
  b[PB_VSCH_SHADE_BIND_NMAP] = photon_nmap ? photon_nmap : photon_accum; /* never read without normal maps */
  if ((r = pb_kernel_bind(g, &v->leaf, b, PB_VSCH_SHADE_BIND_COUNT, ps->accel)) != PB_OK ||
      (r = pb_kernel_bind(g, &v->shade, b, PB_VSCH_SHADE_BIND_COUNT, ps->accel)) != PB_OK ||
      (r = pb_gpu_pipeline_bind(g, &v->blur, b, PB_VSCH_SHADE_BIND_COUNT)) != PB_OK)
    return r;
  v->bound = 1;
  return PB_OK;
}

static pb_result vsch_record(pb_gpu *g, void *impl, uint32_t sample_index, uint32_t pixels, uint32_t flags) {
  vsch *v = impl;
  if (!v->bound) return pb_fail(PB_ERR_INTERNAL, "vsch estimator: recorded before bind");
  if (pixels > v->pixel_cap)
    return pb_fail(PB_ERR_INTERNAL, "vsch estimator: %u pixels, bound for %u", pixels, v->pixel_cap);
  pb_gpu_vsch_push p = v->push;
  p.sample_index = sample_index;
  p.pixels = pixels;
  p.flags = (v->desc.vsch.directional ? PB_VSCH_DIRECTIONAL : 0u) |
            ((flags & PB_GATHER_NO_BEAUTY) ? PB_VSCH_NO_BEAUTY : 0u) |
            (v->desc.lbvh.no_edge_correction ? PB_VSCH_NO_EDGES : 0u);
  const char *abl = getenv("PB_VSCH_ABLATE"); /* benchmark: seed 004 Fig. 9's optimisations off */
  if (abl && strstr(abl, "trivial")) p.flags |= PB_VSCH_NO_TRIVIAL;
  if (abl && strstr(abl, "cone")) p.flags |= PB_VSCH_NO_CONE;
  p.radius = v->desc.vsch.radius;
  p.footprint_scale = v->footprint_scale;
  p.capacity = v->capacity;
  p.host_count = v->stored;
  p.count_from_map = v->counts.buffer ? 1u : 0u;
  uint32_t cap = v->capacity ? v->capacity : 1u;
  pb_result r = PB_OK;
#define STEP(call)                     \
  do {                                 \
    if (r == PB_OK) r = (call);        \
    pb_gpu_barrier(g);                 \
  } while (0)
  pb_gpu_barrier(g); /* the G-buffer */
  STEP(pb_gpu_dispatch(g, &v->pass[P_CLEAR], &p, p.nodes));
  STEP(pb_gpu_dispatch(g, &v->pass[P_RANGE], &p, pixels > cap ? pixels : cap));
  STEP(pb_gpu_dispatch(g, &v->pass[P_MARK], &p, pixels));
  p.level = 0;
  STEP(pb_gpu_dispatch(g, &v->pass[P_SCAN], &p, PB_GPU_WORKGROUP));
  STEP(pb_gpu_dispatch(g, &v->leaf, &p, pixels));
  STEP(pb_gpu_dispatch(g, &v->pass[P_CONE], &p, pixels));
  for (uint32_t L = 1; L <= PB_VSCH_LEVELS; ++L) {
    p.level = L;
    uint32_t end = L < PB_VSCH_LEVELS ? p.level_base[L + 1] : p.nodes; /* level L's nodes */
    STEP(pb_gpu_dispatch(g, &v->pass[P_UP], &p, end - p.level_base[L]));
  }
  STEP(pb_gpu_dispatch(g, &v->pass[P_COUNT], &p, cap));
  p.level = 1;
  STEP(pb_gpu_dispatch(g, &v->pass[P_SCAN], &p, PB_GPU_WORKGROUP));
  STEP(pb_gpu_dispatch(g, &v->pass[P_FILL], &p, cap));
  if (r == PB_OK) r = pb_radix_sort_record(g, v->sort); /* barriers before and after */
  STEP(pb_gpu_dispatch_indirect(g, &v->pass[P_RANGES], &p, &v->data, PB_VSCH_H_ARGS * 4u));
  STEP(pb_gpu_dispatch(g, &v->shade, &p, pixels));
  if (v->desc.vsch.directional) STEP(pb_gpu_dispatch(g, &v->blur, &p, pixels));
#undef STEP
  return r;
}

static uint32_t vsch_stats(pb_gpu *g, void *impl, pb_tracer_stat *out, uint32_t max) {
  vsch *v = impl;
  uint32_t h[PB_VSCH_HEADER_WORDS];
  if (!v->data.buffer || pb_gpu_buffer_download(g, &v->data, 0, h, sizeof h) != PB_OK) return 0;
  const struct {
    const char *name;
    uint32_t word;
  } k[] = {
      {"clusters", PB_VSCH_H_LEAVES},          {"photons", PB_VSCH_H_PHOTONS},
      {"list_pairs", PB_VSCH_H_PAIRS},         {"pairs_dropped", PB_VSCH_H_PAIR_OVERFLOW},
      {"trivial_accepts", PB_VSCH_H_TRIVIAL}, {"cone_rejects", PB_VSCH_H_REJECTED},
      {"directional_adds", PB_VSCH_H_DIRECTIONAL},
  };
  if (h[PB_VSCH_H_PAIR_OVERFLOW] && !v->warned) {
    pb_log_warn("vsch estimator: %u of %u photon list entries dropped (the list was full); later photon maps get "
                "room for them", h[PB_VSCH_H_PAIR_OVERFLOW], h[PB_VSCH_H_LISTED]);
    v->warned = 1;
  }
  uint32_t n = 0;
  for (size_t i = 0; i < sizeof k / sizeof *k && n < max; ++i, ++n) {
    out[n].name = k[i].name;
    out[n].value = h[k[i].word];
    out[n].summed = 0;
  }
  if (n < max) {
    out[n].name = "directional";
    out[n].value = v->desc.vsch.directional ? 1 : 0;
    out[n].summed = 0;
    ++n;
  }
  return n;
}

const pb_estimator_ops pb_estimator_vsch_ops = {
    .name = "vsch",
    .create = vsch_create,
    .update = vsch_update,
    .begin_map = vsch_begin_map,
    .record_build = vsch_record_build,
    .build_done = vsch_build_done,
    .bind = vsch_bind,
    .record = vsch_record,
    .stats = vsch_stats,
    .destroy = vsch_destroy,
};
