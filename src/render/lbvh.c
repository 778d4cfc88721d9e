/* The photon LBVH, built on the GPU for every photon map (seed 000 sections
 * 5-6; shaders/lbvh_*.comp, one kernel per step):
 *   bounds   position bounds (atomics) + footprint areas per workgroup
 *   reduce   area sum -> T_auto = clamp(round(sum / scene area), 1, 256)
 *   morton   30-bit codes within the bounds
 *   sort     LSD radix sort, 8 passes of 4 bits: count / scan / stable
 *            scatter; no subgroup operations (lavapipe runs subgroups of 8)
 *   reorder  photons copied into Morton order
 *   hierarchy  Karras (2012) radix tree, ties broken by sorted index
 *   boxes    per inner node of at most B photons, the union of its
 *            photons' exact ellipsoid AABBs (O(n log B); the atomic
 *            bottom-up climb lost visits on lavapipe)
 *   boxes_top  per larger node, the union of the boxes of the B-bounded
 *            nodes below it (about 2n/B nodes). B bounds every invocation's
 *            loop iterations: llvmpipe stops all loops of an invocation
 *            after 65535 iterations in all, which once cut the root's box
 *            to the first 65535 photons (the gather lost half the map).
 *   finalize leaf merge by T_auto (and of equal-code runs), leaf-end flags
 * All buffers come from the map's capacity, grown when a larger map comes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "render/estimator_internal.h"
#include "shaders/lbvh_bounds.spv.h"
#include "shaders/lbvh_boxes.spv.h"
#include "shaders/lbvh_boxes_top.spv.h"
#include "shaders/lbvh_finalize.spv.h"
#include "shaders/lbvh_hierarchy.spv.h"
#include "shaders/lbvh_morton.spv.h"
#include "shaders/lbvh_reduce.spv.h"
#include "shaders/lbvh_reorder.spv.h"
#include "shaders/lbvh_sort_count.spv.h"
#include "shaders/lbvh_sort_scan.spv.h"
#include "shaders/lbvh_sort_scatter.spv.h"

static double scene_area(const pb_scene *s) {
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

void pb_photon_estimator_update(pb_photon_estimator *e, const pb_scene *s) {
  if (e) e->scene_area = (float)scene_area(s);
}

pb_result pb_photon_estimator_create(pb_gpu *g, const pb_scene *s, const pb_photon_estimate_desc *desc,
                                     pb_photon_estimator **out) {
  *out = NULL;
  pb_photon_estimator *e = calloc(1, sizeof *e);
  if (!e) return pb_fail(PB_ERR_NOMEM, "photon estimator: out of memory");
  if (desc) e->desc = *desc;
  if (e->desc.leaf_size > PB_LBVH_MAX_FIXED_LEAF) {
    free(e);
    return pb_fail(PB_ERR_USAGE, "photon estimator: leaf size %u (at most %u)", desc->leaf_size,
                   (unsigned)PB_LBVH_MAX_FIXED_LEAF);
  }
  e->scene_area = (float)scene_area(s);
  static const struct {
    const char *name;
    const uint32_t *spv;
    size_t bytes;
  } k[PB_LBVH_PASS_N] = {
      {"lbvh.bounds", pb_spv_lbvh_bounds, sizeof pb_spv_lbvh_bounds},
      {"lbvh.reduce", pb_spv_lbvh_reduce, sizeof pb_spv_lbvh_reduce},
      {"lbvh.morton", pb_spv_lbvh_morton, sizeof pb_spv_lbvh_morton},
      {"lbvh.sort_count", pb_spv_lbvh_sort_count, sizeof pb_spv_lbvh_sort_count},
      {"lbvh.sort_scan", pb_spv_lbvh_sort_scan, sizeof pb_spv_lbvh_sort_scan},
      {"lbvh.sort_scatter", pb_spv_lbvh_sort_scatter, sizeof pb_spv_lbvh_sort_scatter},
      {"lbvh.reorder", pb_spv_lbvh_reorder, sizeof pb_spv_lbvh_reorder},
      {"lbvh.hierarchy", pb_spv_lbvh_hierarchy, sizeof pb_spv_lbvh_hierarchy},
      {"lbvh.boxes", pb_spv_lbvh_boxes, sizeof pb_spv_lbvh_boxes},
      {"lbvh.boxes_top", pb_spv_lbvh_boxes_top, sizeof pb_spv_lbvh_boxes_top},
      {"lbvh.finalize", pb_spv_lbvh_finalize, sizeof pb_spv_lbvh_finalize},
  };
  pb_result r = PB_OK;
  for (int i = 0; i < PB_LBVH_PASS_N && r == PB_OK; ++i) {
    pb_gpu_pipeline_desc pd = {.name = k[i].name, .spirv = k[i].spv, .spirv_bytes = k[i].bytes,
                               .binding_count = PB_LBVH_BIND_COUNT, .push_bytes = sizeof(pb_gpu_lbvh_push)};
    r = pb_gpu_pipeline_create(g, &pd, &e->pass[i]);
  }
  pb_gpu_buffer_desc id = {.name = "lbvh.info", .size = sizeof(pb_gpu_lbvh_info), .host_visible = 1};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &id, &e->info);
  pb_gpu_buffer_desc dd = {.name = "lbvh.dummy", .size = 256};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &dd, &e->dummy);
  if (r != PB_OK) {
    pb_photon_estimator_destroy(g, e);
    return r;
  }
  *out = e;
  return PB_OK;
}

static void free_buffers(pb_gpu *g, pb_photon_estimator *e) {
  pb_gpu_buffer_destroy(g, &e->sorted);
  pb_gpu_buffer_destroy(g, &e->keys);
  pb_gpu_buffer_destroy(g, &e->vals);
  pb_gpu_buffer_destroy(g, &e->hist);
  pb_gpu_buffer_destroy(g, &e->nodes);
  pb_gpu_buffer_destroy(g, &e->leaf_parent);
  pb_gpu_buffer_destroy(g, &e->visit);
  pb_gpu_buffer_destroy(g, &e->partial);
  e->capacity = 0;
}

void pb_photon_estimator_set_footprint_scale(pb_photon_estimator *e, float scale) {
  e->footprint_scale = scale > 0.0f && isfinite(scale) ? scale : 1.0f;
}

void pb_photon_estimator_destroy(pb_gpu *g, pb_photon_estimator *e) {
  if (!e) return;
  for (int i = 0; i < PB_LBVH_PASS_N; ++i) pb_gpu_pipeline_destroy(g, &e->pass[i]);
  pb_gpu_pipeline_destroy(g, &e->gather);
  free_buffers(g, e);
  pb_gpu_buffer_destroy(g, &e->info);
  pb_gpu_buffer_destroy(g, &e->dummy);
  free(e);
}

static pb_result reserve(pb_gpu *g, pb_photon_estimator *e, uint32_t n) {
  if (n <= e->capacity && e->capacity) return PB_OK;
  free_buffers(g, e);
  uint64_t cap = n ? n : 1;
  uint64_t tiles = (cap + PB_GPU_WORKGROUP - 1) / PB_GPU_WORKGROUP;
  struct {
    pb_gpu_buffer *b;
    const char *name;
    uint64_t size;
  } list[] = {
      {&e->sorted, "lbvh.photons", cap * sizeof(pb_gpu_photon)},
      {&e->keys, "lbvh.keys", 2 * cap * sizeof(uint32_t)},
      {&e->vals, "lbvh.values", 2 * cap * sizeof(uint32_t)},
      {&e->hist, "lbvh.histogram", PB_LBVH_RADIX * tiles * sizeof(uint32_t)},
      {&e->nodes, "lbvh.nodes", cap * sizeof(pb_gpu_lbvh_node)},
      {&e->leaf_parent, "lbvh.leaf_parent", cap * sizeof(uint32_t)},
      {&e->visit, "lbvh.visit", cap * sizeof(uint32_t)},
      {&e->partial, "lbvh.area_partial", tiles * sizeof(float)},
  };
  for (size_t i = 0; i < sizeof list / sizeof *list; ++i) {
    pb_gpu_buffer_desc d = {.name = list[i].name, .size = list[i].size};
    pb_result r = pb_gpu_buffer_create(g, &d, list[i].b);
    if (r != PB_OK) {
      free_buffers(g, e);
      return r;
    }
  }
  e->capacity = (uint32_t)cap;
  e->gather_ready = 0;
  return PB_OK;
}

pb_result pb_photon_estimator_build(pb_gpu *g, pb_photon_estimator *e, const pb_photon_map *map,
                                    double *gpu_ms) {
  uint32_t n = map->stored < map->capacity ? map->stored : map->capacity;
  if (!map->photons.buffer) n = 0;
  pb_result r = reserve(g, e, n);
  if (r != PB_OK) return r;
  double wall0 = pb_time_now();
  uint32_t tiles = (n + PB_GPU_WORKGROUP - 1) / PB_GPU_WORKGROUP;
  pb_gpu_lbvh_info info;
  memset(&info, 0, sizeof info);
  info.count = n;
  info.root = n == 0 ? PB_LBVH_NONE : (n == 1 ? (PB_LBVH_LEAF | 0u) : 0u);
  info.t_auto = 1;
  info.leaves = n == 1 ? 1 : 0;
  for (int k = 0; k < 3; ++k) info.bmin[k] = 0xffffffffu, info.bmax[k] = 0;
  info.tiles = tiles;
  info.area_tiles = tiles;
  info.scene_area = e->scene_area;
  info.footprint_scale = e->footprint_scale > 0.0f ? e->footprint_scale : 1.0f;
  info.t_fixed = e->desc.leaf_size;
  if ((r = pb_gpu_buffer_upload(g, &e->info, 0, &info, sizeof info)) != PB_OK) return r;
  e->count = n;
  const pb_gpu_buffer *b[PB_LBVH_BIND_COUNT] = {&e->info,  n ? &map->photons : &e->dummy,
                                                &e->sorted, &e->keys, &e->vals, &e->hist, &e->nodes,
                                                &e->leaf_parent, &e->visit, &e->partial};
  for (int i = 0; i < PB_LBVH_PASS_N; ++i)
    if ((r = pb_gpu_pipeline_bind(g, &e->pass[i], b, PB_LBVH_BIND_COUNT)) != PB_OK) return r;
  e->gather_ready = 0;
  if (n == 0) {
    if (gpu_ms) *gpu_ms = 0.0;
    e->stats.build_ms = 0.0;
    e->stats.sort_ms = 0.0;
    return PB_OK;
  }
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  pb_gpu_timestamp(g, 0);
  pb_gpu_lbvh_push push = {.count = n};
  uint64_t tiled = (uint64_t)tiles * PB_GPU_WORKGROUP;
#define DISPATCH(which, inv)                                                     \
  do {                                                                          \
    if (r == PB_OK) r = pb_gpu_dispatch(g, &e->pass[which], &push, (inv));       \
    pb_gpu_barrier(g);                                                          \
  } while (0)
  DISPATCH(PB_LBVH_PASS_BOUNDS, tiled);
  DISPATCH(PB_LBVH_PASS_REDUCE, PB_GPU_WORKGROUP);
  DISPATCH(PB_LBVH_PASS_MORTON, n);
  pb_gpu_timestamp(g, 2);
  for (uint32_t p = 0; p < PB_LBVH_SORT_PASSES; ++p) {
    push.shift = p * PB_LBVH_RADIX_BITS;
    push.src = (p & 1u) ? e->capacity : 0u;
    push.dst = (p & 1u) ? 0u : e->capacity;
    DISPATCH(PB_LBVH_PASS_COUNT_DIGITS, tiled);
    DISPATCH(PB_LBVH_PASS_SCAN, PB_GPU_WORKGROUP);
    DISPATCH(PB_LBVH_PASS_SCATTER, tiled);
  }
  pb_gpu_timestamp(g, 3);
  /* An even number of passes: the sorted keys and values are at offset 0. */
  push.shift = push.src = push.dst = 0;
  DISPATCH(PB_LBVH_PASS_REORDER, n);
  if (n >= 2) {
    push.count = n - 1;
    DISPATCH(PB_LBVH_PASS_HIERARCHY, n - 1);
    /* B: interval loops of at most B photons in lbvh_boxes, a traversal of
     * about 4n/B nodes in lbvh_boxes_top (both << 65535, see above). */
    push.src = n / 4096u > PB_LBVH_BOX_INTERVAL ? n / 4096u : PB_LBVH_BOX_INTERVAL;
    DISPATCH(PB_LBVH_PASS_BOXES, n - 1);
    DISPATCH(PB_LBVH_PASS_BOXES_TOP, n - 1);
    push.src = 0;
    DISPATCH(PB_LBVH_PASS_FINALIZE, n - 1);
  }
#undef DISPATCH
  pb_gpu_timestamp(g, 1);
  pb_result rs = pb_gpu_submit(g);
  if (r == PB_OK) r = rs;
  if (r != PB_OK) return r;
  double ms = pb_gpu_elapsed_ms(g, 0, 1);
  if (ms < 0) ms = (pb_time_now() - wall0) * 1e3;
  e->stats.build_ms = ms;
  e->stats.sort_ms = pb_gpu_elapsed_ms(g, 2, 3);
  if (gpu_ms) *gpu_ms = ms;
  return PB_OK;
}

pb_result pb_photon_estimator_stats(pb_gpu *g, pb_photon_estimator *e, pb_photon_estimate_stats *out) {
  pb_gpu_lbvh_info info;
  pb_result r = pb_gpu_buffer_download(g, &e->info, 0, &info, sizeof info);
  if (r != PB_OK) return r;
  e->stats.photons = info.count;
  e->stats.t_auto = info.t_computed ? info.t_computed : info.t_auto;
  e->stats.leaf_size = info.t_auto;
  e->stats.leaves = info.leaves;
  e->stats.area_sum = info.area_sum;
  e->stats.scene_area = info.scene_area;
  e->stats.stack_overflow = info.stack_overflow;
  *out = e->stats;
  return PB_OK;
}

void pb_photon_estimator_lbvh(const pb_photon_estimator *e, pb_photon_lbvh_view *out) {
  out->nodes = &e->nodes;
  out->photons = &e->sorted;
  out->keys = &e->keys;
  out->info = &e->info;
  out->count = e->count;
}
