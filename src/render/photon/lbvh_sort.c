/* GPU radix sort (lbvh_sort.h; kernels in shaders/common/lbvh_sort.glsl). */
#include <stdlib.h>

#include "core/log.h"
#include "render/photon/lbvh_sort.h"
#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"
#include "shaders/lbvh_sort_downsweep.spv.h"
#include "shaders/lbvh_sort_downsweep_serial.spv.h"
#include "shaders/lbvh_sort_downsweep_sg.spv.h"
#include "shaders/lbvh_sort_setup.spv.h"
#include "shaders/lbvh_sort_spine.spv.h"
#include "shaders/lbvh_sort_upsweep.spv.h"
#include "shaders/lbvh_sort_upsweep_serial.spv.h"

enum { SETUP = 0, UPSWEEP, SPINE, DOWNSWEEP, KERNELS };
/* Bindings: PB_SORT_BIND_* (shaders/shared/pb_contract.h). */

struct pb_radix_sort {
  pb_radix_sort_desc desc;
  uint32_t passes;
  uint32_t digit_bits;           /* every pass's but the last's (that one: the key bits left) */
  pb_radix_sort_path path;       /* never AUTO */
  pb_gpu_pipeline k[KERNELS];
  pb_gpu_buffer state, keys, vals, hist;
  const pb_gpu_buffer *count;    /* bound count buffer (not owned) */
  uint32_t count_word;
};

/* Subgroup ballots and shuffles in compute, subgroups of 8..64 dividing the
 * workgroup (the _sg kernel keeps per-subgroup counts for at most 8
 * subgroups). */
static int has_subgroups(const pb_gpu *g) {
  const pb_gpu_limits *lim = pb_gpu_get_limits(g);
  const uint32_t need = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_BALLOT_BIT | VK_SUBGROUP_FEATURE_SHUFFLE_BIT;
  uint32_t s = lim->subgroup_size;
  return (lim->subgroup_ops & need) == need && s >= 8 && s <= PB_GPU_WORKGROUP && PB_GPU_WORKGROUP % s == 0;
}

const char *pb_radix_sort_path_name(pb_radix_sort_path p) {
  switch (p) {
  case PB_SORT_PATH_PORTABLE: return "portable";
  case PB_SORT_PATH_SUBGROUP: return "subgroup";
  case PB_SORT_PATH_SERIAL: return "serial";
  default: return "auto";
  }
}

pb_result pb_radix_sort_create(pb_gpu *g, const pb_radix_sort_desc *desc, pb_radix_sort **out) {
  *out = NULL;
  pb_radix_sort *s = calloc(1, sizeof *s);
  if (!s) return pb_fail(PB_ERR_NOMEM, "radix sort: out of memory");
  if (desc) s->desc = *desc;
  uint32_t bits = s->desc.key_bits ? s->desc.key_bits : 32;
  if (bits > 32) {
    free(s);
    return pb_fail(PB_ERR_INTERNAL, "radix sort: %u key bits", bits);
  }
  s->path = s->desc.path;
  if (s->path == PB_SORT_PATH_AUTO)
    s->path = pb_gpu_get_limits(g)->cpu ? PB_SORT_PATH_SERIAL : PB_SORT_PATH_SUBGROUP;
  if (s->path == PB_SORT_PATH_SUBGROUP && !has_subgroups(g)) s->path = PB_SORT_PATH_PORTABLE;
  /* The serial path's digit width, PB_SORT_SERIAL_BITS = 8, from its cost
   * per key and pass on lavapipe (2 cores, 1.4 M random 30-bit keys, CPU
   * time, three interleaved runs, bench/README.md 2026-12-04): 8-bit digits
   * 8.9-9.3 ns, 9-bit 8.7-10.3, 10-bit 14.6-15.4, 11-bit 16.9-18.3. A pass
   * is its scatter (a key and its value to 2^b output runs per tile, 8 tiles
   * a SIMD vector) plus 2^b counters per 4096-key tile to clear, write, scan
   * and read, and both grow with 2^b past 8 bits faster than the passes
   * fall: 30 bits in 4 passes of 8 bits cost ~36 ns a key, in 3 of 10 ~45,
   * 3 of 11 (11 + 11 + 8) ~53, and 9 bits still take 4 passes. (2 passes
   * of 15 bits would need 32768 counters per tile: 8 per key at this tile
   * size.) */
  uint32_t db = PB_SORT_RADIX_BITS;
  if (s->path == PB_SORT_PATH_SERIAL) db = s->desc.digit_bits ? s->desc.digit_bits : PB_SORT_SERIAL_BITS;
  if (db < PB_SORT_MIN_RADIX_BITS || db > PB_SORT_MAX_RADIX_BITS) {
    free(s);
    return pb_fail(PB_ERR_INTERNAL, "radix sort: %u-bit digits (%u..%u)", db, PB_SORT_MIN_RADIX_BITS,
                   PB_SORT_MAX_RADIX_BITS);
  }
  if (db > bits) db = bits; /* one pass */
  s->digit_bits = db;
  s->passes = (bits + db - 1) / db; /* <= PB_SORT_MAX_PASSES: db >= PB_SORT_MIN_RADIX_BITS */
  /* Each kernel for each path. */
  static const struct {
    const char *name;
    const uint32_t *spv;
    size_t bytes;
  } k[3][KERNELS] = {
      [PB_SORT_PATH_PORTABLE - 1] =
          {
              {"sort.setup", pb_spv_lbvh_sort_setup, sizeof pb_spv_lbvh_sort_setup},
              {"sort.upsweep", pb_spv_lbvh_sort_upsweep, sizeof pb_spv_lbvh_sort_upsweep},
              {"sort.spine", pb_spv_lbvh_sort_spine, sizeof pb_spv_lbvh_sort_spine},
              {"sort.downsweep", pb_spv_lbvh_sort_downsweep, sizeof pb_spv_lbvh_sort_downsweep},
          },
      [PB_SORT_PATH_SUBGROUP - 1] =
          {
              {"sort.setup", pb_spv_lbvh_sort_setup, sizeof pb_spv_lbvh_sort_setup},
              {"sort.upsweep", pb_spv_lbvh_sort_upsweep, sizeof pb_spv_lbvh_sort_upsweep},
              {"sort.spine", pb_spv_lbvh_sort_spine, sizeof pb_spv_lbvh_sort_spine},
              {"sort.downsweep_sg", pb_spv_lbvh_sort_downsweep_sg, sizeof pb_spv_lbvh_sort_downsweep_sg},
          },
      [PB_SORT_PATH_SERIAL - 1] =
          {
              {"sort.setup", pb_spv_lbvh_sort_setup, sizeof pb_spv_lbvh_sort_setup},
              {"sort.upsweep_serial", pb_spv_lbvh_sort_upsweep_serial, sizeof pb_spv_lbvh_sort_upsweep_serial},
              {"sort.spine", pb_spv_lbvh_sort_spine, sizeof pb_spv_lbvh_sort_spine},
              {"sort.downsweep_serial", pb_spv_lbvh_sort_downsweep_serial,
               sizeof pb_spv_lbvh_sort_downsweep_serial},
          },
  };
  pb_result r = PB_OK;
  for (int i = 0; i < KERNELS && r == PB_OK; ++i) {
    const int p = (int)s->path - 1;
    pb_gpu_pipeline_desc pd = {.name = k[p][i].name,
                               .spirv = k[p][i].spv,
                               .spirv_bytes = k[p][i].bytes,
                               .binding_count = PB_SORT_BIND_COUNT,
                               .push_bytes = sizeof(pb_gpu_sort_push)};
    r = pb_gpu_pipeline_create(g, &pd, &s->k[i]);
  }
  pb_gpu_buffer_desc sd = {.name = "sort.state", .size = sizeof(pb_gpu_sort_state)};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &sd, &s->state);
  if (r == PB_OK) r = pb_radix_sort_reserve(g, s, s->desc.capacity ? s->desc.capacity : 1);
  if (r != PB_OK) {
    pb_radix_sort_destroy(g, s);
    return r;
  }
  *out = s;
  return PB_OK;
}

static void free_buffers(pb_gpu *g, pb_radix_sort *s) {
  pb_gpu_buffer_destroy(g, &s->keys);
  pb_gpu_buffer_destroy(g, &s->vals);
  pb_gpu_buffer_destroy(g, &s->hist);
  s->desc.capacity = 0;
  s->count = NULL;
}

void pb_radix_sort_destroy(pb_gpu *g, pb_radix_sort *s) {
  if (!s) return;
  for (int i = 0; i < KERNELS; ++i) pb_gpu_pipeline_destroy(g, &s->k[i]);
  free_buffers(g, s);
  pb_gpu_buffer_destroy(g, &s->state);
  free(s);
}

pb_result pb_radix_sort_reserve(pb_gpu *g, pb_radix_sort *s, uint32_t capacity) {
  if (capacity > UINT32_MAX - 3) return pb_fail(PB_ERR_LIMIT, "radix sort: %u keys", capacity);
  capacity = capacity ? (capacity + 3u) & ~3u : 4u; /* the upsweep reads 4 keys at a time */
  if (s->keys.buffer && capacity <= s->desc.capacity) return PB_OK;
  free_buffers(g, s);
  const uint32_t tile = s->path == PB_SORT_PATH_SERIAL ? PB_SORT_SERIAL_TILE : PB_SORT_TILE;
  uint64_t tiles = ((uint64_t)capacity + tile - 1) / tile;
  pb_gpu_buffer_desc kd = {.name = "sort.keys", .size = 2ull * capacity * sizeof(uint32_t)};
  pb_gpu_buffer_desc vd = {.name = "sort.values", .size = 2ull * capacity * sizeof(uint32_t)};
  /* The workgroup paths' upsweep writes all PB_SORT_RADIX counts of a tile. */
  uint64_t radix = s->path == PB_SORT_PATH_SERIAL ? 1u << s->digit_bits : PB_SORT_RADIX;
  pb_gpu_buffer_desc hd = {.name = "sort.histogram", .size = radix * tiles * sizeof(uint32_t)};
  pb_result r = pb_gpu_buffer_create(g, &kd, &s->keys);
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &vd, &s->vals);
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &hd, &s->hist);
  if (r != PB_OK) {
    free_buffers(g, s);
    return r;
  }
  s->desc.capacity = capacity;
  return PB_OK;
}

uint32_t pb_radix_sort_capacity(const pb_radix_sort *s) { return s->desc.capacity; }
pb_radix_sort_path pb_radix_sort_get_path(const pb_radix_sort *s) { return s->path; }
const pb_gpu_buffer *pb_radix_sort_keys(const pb_radix_sort *s) { return &s->keys; }
const pb_gpu_buffer *pb_radix_sort_vals(const pb_radix_sort *s) { return &s->vals; }
uint32_t pb_radix_sort_result(const pb_radix_sort *s) { return (s->passes & 1u) ? s->desc.capacity : 0u; }
uint32_t pb_radix_sort_passes(const pb_radix_sort *s) { return s->passes; }
uint32_t pb_radix_sort_digit_bits(const pb_radix_sort *s) { return s->digit_bits; }

pb_result pb_radix_sort_bind(pb_gpu *g, pb_radix_sort *s, const pb_gpu_buffer *count, uint32_t count_word) {
  if (!count || (uint64_t)count_word * 4 + 4 > count->size)
    return pb_fail(PB_ERR_INTERNAL, "radix sort: count word %u outside its buffer", count_word);
  const pb_gpu_buffer *b[PB_SORT_BIND_COUNT] = {
      [PB_SORT_BIND_STATE] = &s->state, [PB_SORT_BIND_KEYS] = &s->keys,     [PB_SORT_BIND_VALS] = &s->vals,
      [PB_SORT_BIND_HIST] = &s->hist,   [PB_SORT_BIND_COUNT_SRC] = count,   [PB_SORT_BIND_KEYS4] = &s->keys,
      [PB_SORT_BIND_VALS4] = &s->vals};
  for (int i = 0; i < KERNELS; ++i) {
    pb_result r = pb_gpu_pipeline_bind(g, &s->k[i], b, PB_SORT_BIND_COUNT);
    if (r != PB_OK) return r;
  }
  s->count = count;
  s->count_word = count_word;
  return PB_OK;
}

pb_result pb_radix_sort_record(pb_gpu *g, pb_radix_sort *s) {
  if (!s->count) return pb_fail(PB_ERR_INTERNAL, "radix sort: recorded before pb_radix_sort_bind");
  pb_gpu_sort_push push = {.count_word = s->count_word,
                           .capacity = s->desc.capacity,
                           .max_groups_x = pb_gpu_get_limits(g)->max_workgroup_count_x,
                           .tile = s->path == PB_SORT_PATH_SERIAL ? PB_SORT_SERIAL_TILE : PB_SORT_TILE,
                           .bits = s->digit_bits};
  const uint64_t tile_args = s->path == PB_SORT_PATH_SERIAL ? offsetof(pb_gpu_sort_state, serial_args)
                                                             : offsetof(pb_gpu_sort_state, tile_args);
  const uint64_t spine_args = offsetof(pb_gpu_sort_state, spine_args);
  pb_gpu_barrier(g);
  pb_result r = pb_gpu_dispatch(g, &s->k[SETUP], &push, PB_GPU_WORKGROUP);
  pb_gpu_barrier(g);
  const uint32_t bits = s->desc.key_bits ? s->desc.key_bits : 32;
  for (uint32_t p = 0; p < s->passes && r == PB_OK; ++p) {
    push.shift = p * s->digit_bits;
    push.bits = bits - push.shift < s->digit_bits ? bits - push.shift : s->digit_bits;
    push.pass = p;
    push.src = (p & 1u) ? s->desc.capacity : 0u;
    push.dst = (p & 1u) ? 0u : s->desc.capacity;
    r = pb_gpu_dispatch_indirect(g, &s->k[UPSWEEP], &push, &s->state, tile_args);
    pb_gpu_barrier(g);
    if (r == PB_OK) r = pb_gpu_dispatch_indirect(g, &s->k[SPINE], &push, &s->state, spine_args);
    pb_gpu_barrier(g);
    if (r == PB_OK) r = pb_gpu_dispatch_indirect(g, &s->k[DOWNSWEEP], &push, &s->state, tile_args);
    pb_gpu_barrier(g);
  }
  return r;
}
