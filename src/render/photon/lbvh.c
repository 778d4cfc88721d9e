/* The photon LBVH, built on the GPU for every photon map (seed 000 sections
 * 5-6), recorded as one stretch of dispatches with no host round trip: the
 * map's photon count is read by the GPU (lbvh_setup) and every later pass is
 * sized from it with an indirect dispatch.
 *   setup    count, state, grids (one invocation)
 *   bounds   position bounds + footprint areas per tile; the last tile's
 *            workgroup sets T_auto and the Morton box
 *   morton   30-bit codes and indices (the sort's keys and values)
 *   sort     radix sort, 4 passes of 8 bits (lbvh_sort.c)
 *   climb    photons copied into Morton order, hierarchy, boxes and leaf
 *            merge by T_auto in one bottom-up pass (Apetrei 2014)
 * 17 dispatches in all. Every buffer comes from the map's capacity (grown
 * when a larger map comes), never from a count read back; frame.c records
 * the build in the tracer's submission, behind its dispatch. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "render/estimate/estimator_internal.h"
#include "shaders/lbvh_bounds.spv.h"
#include "shaders/lbvh_climb.spv.h"
#include "shaders/lbvh_morton.spv.h"
#include "shaders/lbvh_setup.spv.h"

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
      {"lbvh.setup", pb_spv_lbvh_setup, sizeof pb_spv_lbvh_setup},
      {"lbvh.bounds", pb_spv_lbvh_bounds, sizeof pb_spv_lbvh_bounds},
      {"lbvh.morton", pb_spv_lbvh_morton, sizeof pb_spv_lbvh_morton},
      {"lbvh.climb", pb_spv_lbvh_climb, sizeof pb_spv_lbvh_climb},
  };
  pb_result r = PB_OK;
  /* lbvh_climb's fences (SC_FENCES) order a child's entry before its visit
   * count and the sibling's read after it. On llvmpipe (Mesa 22.3) a
   * memoryBarrierBuffer() inside the climb's divergent loop, or an atomic
   * with acquire/release semantics, which NIR lowers to the same barrier,
   * made lanes skip the rest of the shader (the root was never finished).
   * There the fences are not needed: llvmpipe emits every atomic as an LLVM
   * seq_cst read-modify-write (gallivm lp_bld_nir_soa.c, emit_atomic_mem),
   * which no load or store crosses. */
  uint32_t fences = pb_gpu_get_limits(g)->driver_id != VK_DRIVER_ID_MESA_LLVMPIPE;
  for (int i = 0; i < PB_LBVH_PASS_N && r == PB_OK; ++i) {
    pb_gpu_pipeline_desc pd = {.name = k[i].name, .spirv = k[i].spv, .spirv_bytes = k[i].bytes,
                               .binding_count = PB_LBVH_BIND_COUNT, .push_bytes = sizeof(pb_gpu_lbvh_push),
                               .spec = i == PB_LBVH_PASS_CLIMB ? &fences : NULL, /* PB_SPEC_FENCES */
                               .spec_count = i == PB_LBVH_PASS_CLIMB ? PB_SPEC_FENCES_COUNT : 0};
    r = pb_gpu_pipeline_create(g, &pd, &e->pass[i]);
  }
  pb_gpu_buffer_desc id = {.name = "lbvh.info", .size = sizeof(pb_gpu_lbvh_info), .readback = 1};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &id, &e->info);
  pb_gpu_buffer_desc dd = {.name = "lbvh.dummy", .size = 256};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &dd, &e->dummy);
  pb_radix_sort_desc sd = {.key_bits = PB_LBVH_MORTON_BITS};
  if (r == PB_OK) r = pb_radix_sort_create(g, &sd, &e->sort);
  if (r != PB_OK) {
    pb_photon_estimator_destroy(g, e);
    return r;
  }
  *out = e;
  return PB_OK;
}

static void free_buffers(pb_gpu *g, pb_photon_estimator *e) {
  pb_gpu_buffer_destroy(g, &e->sorted);
  pb_gpu_buffer_destroy(g, &e->nodes);
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
  pb_gpu_pipeline_destroy(g, &e->gather_ups);
  free_buffers(g, e);
  pb_radix_sort_destroy(g, e->sort);
  pb_gpu_buffer_destroy(g, &e->info);
  pb_gpu_buffer_destroy(g, &e->dummy);
  free(e);
}

/* Buffers for `cap` photons: the sorted copies, the nodes (count - 1 inner
 * nodes and the one-leaf root's slot), the climb's visit counters, the
 * bounds tiles' area sums, the sort's keys and values. */
static pb_result reserve(pb_gpu *g, pb_photon_estimator *e, uint32_t cap) {
  if (cap == 0) cap = 1;
  if (cap <= e->capacity) return PB_OK;
  free_buffers(g, e);
  uint64_t tiles = ((uint64_t)cap + PB_LBVH_BOUNDS_TILE - 1) / PB_LBVH_BOUNDS_TILE;
  struct {
    pb_gpu_buffer *b;
    const char *name;
    uint64_t size;
  } list[] = {
      {&e->sorted, "lbvh.photons", (uint64_t)cap * sizeof(pb_gpu_photon_packed)},
      {&e->nodes, "lbvh.nodes", (uint64_t)cap * sizeof(pb_gpu_lbvh_node)},
      {&e->visit, "lbvh.visit", (uint64_t)cap * sizeof(uint32_t)},
      {&e->partial, "lbvh.area_partial", tiles * sizeof(float)},
  };
  pb_result r = PB_OK;
  for (size_t i = 0; i < sizeof list / sizeof *list && r == PB_OK; ++i) {
    pb_gpu_buffer_desc d = {.name = list[i].name, .size = list[i].size};
    r = pb_gpu_buffer_create(g, &d, list[i].b);
  }
  if (r == PB_OK) r = pb_radix_sort_reserve(g, e->sort, cap);
  if (r == PB_OK) r = pb_radix_sort_bind(g, e->sort, &e->info, offsetof(pb_gpu_lbvh_info, count) / 4);
  if (r != PB_OK) {
    free_buffers(g, e);
    return r;
  }
  e->capacity = cap;
  e->gather_ready = 0;
  e->gather_ups_ready = 0;
  return PB_OK;
}

/* Timestamp slots of a build, after ts_slot: start, after bounds, after
 * Morton, after the sort, end. */
enum { TS_START = 0, TS_BOUNDS, TS_MORTON, TS_SORT, TS_END };

pb_result pb_photon_estimator_prepare(pb_gpu *g, pb_photon_estimator *e, const pb_photon_map *map) {
  pb_result r = reserve(g, e, map->capacity);
  if (r != PB_OK) return r;
  int from_map = map->counts.buffer != VK_NULL_HANDLE;
  pb_gpu_lbvh_push push = {
      .capacity = map->photons.buffer ? map->capacity : 0,
      .host_count = map->stored,
      .flags = from_map ? PB_LBVH_COUNT_FROM_MAP : 0u,
      .max_groups_x = pb_gpu_get_limits(g)->max_workgroup_count_x,
      .scene_area = e->scene_area,
      .footprint_scale = e->footprint_scale > 0.0f ? e->footprint_scale : 1.0f,
      .t_fixed = e->desc.leaf_size,
      .sorted = pb_radix_sort_result(e->sort),
  };
  e->push = push;
  const pb_gpu_buffer *in = map->photons.buffer ? &map->photons : &e->dummy;
  const pb_gpu_buffer *b[PB_LBVH_BIND_COUNT] = {
      [PB_LBVH_BIND_INFO] = &e->info, [PB_LBVH_BIND_PHOTONS_IN] = in,
      [PB_LBVH_BIND_MAP_COUNTS] = from_map ? &map->counts : &e->dummy, [PB_LBVH_BIND_SORTED] = &e->sorted,
      [PB_LBVH_BIND_KEYS] = pb_radix_sort_keys(e->sort), [PB_LBVH_BIND_VALS] = pb_radix_sort_vals(e->sort),
      [PB_LBVH_BIND_NODES] = &e->nodes, [PB_LBVH_BIND_VISIT] = &e->visit, [PB_LBVH_BIND_PARTIAL] = &e->partial,
      [PB_LBVH_BIND_PHOTONS_IN4] = in, [PB_LBVH_BIND_SORTED4] = &e->sorted, [PB_LBVH_BIND_NODES4] = &e->nodes};
  for (int i = 0; i < PB_LBVH_PASS_N; ++i)
    if ((r = pb_gpu_pipeline_bind(g, &e->pass[i], b, PB_LBVH_BIND_COUNT)) != PB_OK) return r;
  e->gather_ready = 0;
  e->gather_ups_ready = 0;
  return PB_OK;
}

pb_result pb_photon_estimator_record_build(pb_gpu *g, pb_photon_estimator *e, uint32_t ts) {
  const pb_gpu_lbvh_push *push = &e->push;
  const uint64_t photon_args = offsetof(pb_gpu_lbvh_info, photon_args);
  const uint64_t tile_args = offsetof(pb_gpu_lbvh_info, tile_args);
  pb_gpu_barrier(g); /* the map's photons and counts, written by the tracer */
  pb_gpu_timestamp(g, ts + TS_START);
  pb_result r = pb_gpu_dispatch(g, &e->pass[PB_LBVH_PASS_SETUP], push, 1);
  pb_gpu_barrier(g);
  if (r == PB_OK) r = pb_gpu_dispatch_indirect(g, &e->pass[PB_LBVH_PASS_BOUNDS], push, &e->info, tile_args);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, ts + TS_BOUNDS);
  if (r == PB_OK) r = pb_gpu_dispatch_indirect(g, &e->pass[PB_LBVH_PASS_MORTON], push, &e->info, photon_args);
  pb_gpu_timestamp(g, ts + TS_MORTON);
  if (r == PB_OK) r = pb_radix_sort_record(g, e->sort); /* barriers before and after */
  pb_gpu_timestamp(g, ts + TS_SORT);
  if (r == PB_OK) r = pb_gpu_dispatch_indirect(g, &e->pass[PB_LBVH_PASS_CLIMB], push, &e->info, photon_args);
  pb_gpu_barrier(g);
  pb_gpu_timestamp(g, ts + TS_END);
  return r;
}

void pb_photon_estimator_build_done(pb_gpu *g, pb_photon_estimator *e, uint32_t ts, double *gpu_ms) {
  double ms = pb_gpu_elapsed_ms(g, ts + TS_START, ts + TS_END);
  e->stats.build_ms = ms;
  e->stats.bounds_ms = pb_gpu_elapsed_ms(g, ts + TS_START, ts + TS_BOUNDS);
  e->stats.morton_ms = pb_gpu_elapsed_ms(g, ts + TS_BOUNDS, ts + TS_MORTON);
  e->stats.sort_ms = pb_gpu_elapsed_ms(g, ts + TS_MORTON, ts + TS_SORT);
  e->stats.climb_ms = pb_gpu_elapsed_ms(g, ts + TS_SORT, ts + TS_END);
  if (gpu_ms) *gpu_ms = ms;
}

pb_result pb_photon_estimator_build(pb_gpu *g, pb_photon_estimator *e, const pb_photon_map *map,
                                    double *gpu_ms) {
  pb_result r = pb_photon_estimator_prepare(g, e, map);
  if (r != PB_OK) return r;
  double wall0 = pb_time_now();
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  r = pb_photon_estimator_record_build(g, e, 0);
  pb_result rs = pb_gpu_submit(g);
  if (r == PB_OK) r = rs;
  if (r != PB_OK) return r;
  pb_photon_estimator_build_done(g, e, 0, gpu_ms);
  if (e->stats.build_ms < 0) {
    e->stats.build_ms = (pb_time_now() - wall0) * 1e3;
    if (gpu_ms) *gpu_ms = e->stats.build_ms;
  }
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
  out->keys = pb_radix_sort_keys(e->sort);
  out->order = pb_radix_sort_vals(e->sort);
  out->sorted_offset = pb_radix_sort_result(e->sort);
  out->info = &e->info;
  out->count = e->stats.photons;
}
