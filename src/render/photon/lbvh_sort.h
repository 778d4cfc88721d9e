/* GPU radix sort of 32-bit keys with 32-bit values (the photon LBVH's Morton
 * codes and photon indices; shaders/lbvh_sort_*.comp, constants and state in
 * shaders/shared/pb_lbvh.h): LSD, reduce-then-scan, stable; 8-bit digits
 * (the serial path takes 8..11 for benchmarks; lbvh_sort.c derives its
 * default, 8, from lavapipe's measured per-pass cost), as many passes as the
 * key bits need, the last only as wide as the bits left (30-bit Morton
 * codes: 8 + 8 + 8 + 6).
 *
 * The number of keys is read on the GPU from a word of a caller's buffer
 * (clamped to the capacity), so a sort records into an open command buffer
 * behind the pass that writes its keys and count, with no host round trip:
 * one setup dispatch, then per pass an upsweep, a spine and a downsweep, all
 * sized indirectly. Three ways to rank a tile (pb_radix_sort_path): on
 * GPUs whose compute stage has subgroup ballots and shuffles with subgroups
 * of 8 to 64 invocations (NVIDIA: 32, AMD: 32/64), subgroups rank their
 * chunks of the tile; without them, workgroup barriers and shared atomics;
 * on CPU implementations (lavapipe, whose subgroups of 8 have all these
 * operations) one invocation ranks a whole tile, 3-5x faster there than
 * either (bench/README.md). */
#ifndef PB_RENDER_LBVH_SORT_H
#define PB_RENDER_LBVH_SORT_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"

/* How a tile's keys are counted and ranked (the passes, tiles, histogram
 * and spine are the same). */
typedef enum pb_radix_sort_path {
  PB_SORT_PATH_AUTO = 0, /* SERIAL on CPU devices, else SUBGROUP where the
                            device has it, else PORTABLE */
  PB_SORT_PATH_PORTABLE, /* a workgroup per tile, barriers and shared atomics */
  PB_SORT_PATH_SUBGROUP, /* a workgroup per tile, subgroups rank their chunks */
  PB_SORT_PATH_SERIAL    /* an invocation per tile, counters in private memory */
} pb_radix_sort_path;

/* Zero means default for every field. */
typedef struct pb_radix_sort_desc {
  uint32_t capacity;  /* keys at most (grown by pb_radix_sort_reserve); 0: 1 */
  uint32_t key_bits;  /* low bits that can be set (1..32); 0: 32 */
  pb_radix_sort_path path; /* SUBGROUP where the device lacks it: PORTABLE */
  uint32_t digit_bits; /* serial path only (benchmarks): digit width,
                          PB_SORT_MIN_RADIX_BITS..PB_SORT_MAX_RADIX_BITS;
                          0: PB_SORT_SERIAL_BITS (8). The workgroup paths: 8 */
} pb_radix_sort_desc;

typedef struct pb_radix_sort pb_radix_sort;

pb_result pb_radix_sort_create(pb_gpu *g, const pb_radix_sort_desc *desc, pb_radix_sort **out);
void pb_radix_sort_destroy(pb_gpu *g, pb_radix_sort *s);
/* Grows the buffers to hold `capacity` keys, rounded up to a multiple of 4
 * (contents are lost; bind again). */
pb_result pb_radix_sort_reserve(pb_gpu *g, pb_radix_sort *s, uint32_t capacity);
uint32_t pb_radix_sort_capacity(const pb_radix_sort *s);
/* The path in use (never AUTO). */
pb_radix_sort_path pb_radix_sort_get_path(const pb_radix_sort *s);
const char *pb_radix_sort_path_name(pb_radix_sort_path p);

/* The key and value buffers, uint[2 x capacity] each: the caller writes the
 * input to elements 0 .. n-1; the sorted keys and values are at
 * pb_radix_sort_result() .. + n-1 (0 for an even number of passes). */
const pb_gpu_buffer *pb_radix_sort_keys(const pb_radix_sort *s);
const pb_gpu_buffer *pb_radix_sort_vals(const pb_radix_sort *s);
uint32_t pb_radix_sort_result(const pb_radix_sort *s);
/* Passes: ceil(key bits / digit width), every digit that wide but the last,
 * which takes the key bits left. */
uint32_t pb_radix_sort_passes(const pb_radix_sort *s);
uint32_t pb_radix_sort_digit_bits(const pb_radix_sort *s);

/* n = min(count[count_word], capacity), read by the GPU when the sort runs.
 * Call after create/reserve and whenever the count buffer changes. */
pb_result pb_radix_sort_bind(pb_gpu *g, pb_radix_sort *s, const pb_gpu_buffer *count, uint32_t count_word);
/* Records the sort into the open command buffer, a barrier before (the
 * keys, values and count written by earlier passes) and after. */
pb_result pb_radix_sort_record(pb_gpu *g, pb_radix_sort *s);

#endif
