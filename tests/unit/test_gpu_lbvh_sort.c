/* The GPU radix sort (src/render/photon/lbvh_sort.c) against a stable host sort of
 * the same (key, value) pairs, on every path the device can run: serial
 * (the one CPU devices take), subgroup (where the device has ballots and
 * shuffles; lavapipe: subgroups of 8) and portable. Every sorted key and value must equal the host's (so the sort is a
 * stable permutation: equal keys keep their input order). Cases: 0, 1, 2
 * keys, one tile and its neighbours (1023, 1024, 1025), partial tiles,
 * random 30-bit Morton-like keys, full 32-bit keys, all keys equal, 5
 * distinct keys (one digit dominates every tile), already sorted and
 * reversed input, 1 to 4 passes (the result in the second half for odd
 * pass counts), the key count read on the GPU from a word of another buffer
 * and clamped to the capacity, the buffers grown between sorts, and
 * 1.5 M keys. Digit widths: 8 bits on the workgroup paths and by default on
 * the serial path (30-bit keys: 8 + 8 + 8 + 6), and every other width the
 * serial path takes (9, 10: 30 bits in 3 passes, 11: 11 + 11 + 8), with key
 * widths whose last pass is narrower (21 = 8 + 8 + 5, 10 + 10 + 1; 16, 24,
 * 32 = 10 + 10 + 10 + 2). Validation layers on,
 * any message fatal; exit 77 without a Vulkan device. */
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "core/log.h"
#include "render/photon/lbvh_sort.h"

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static uint32_t urand(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (uint32_t)(rng_state >> 32);
}

typedef struct pair {
  uint32_t key, val;
} pair;

static int cmp_pair(const void *a, const void *b) {
  const pair *x = a, *y = b;
  if (x->key != y->key) return x->key < y->key ? -1 : 1;
  return x->val < y->val ? -1 : (x->val > y->val); /* values are input positions: stable */
}

enum { RANDOM, EQUAL, FEW, SORTED, REVERSED };

/* Sorts n keys of `bits` bits (distribution `kind`); the count goes through
 * word 3 of a count buffer holding `count_word_value` (n unless testing the
 * clamp to the capacity). */
static void sort_case(pb_gpu *g, pb_radix_sort *s, uint32_t n, uint32_t bits, int kind, uint32_t count_word_value,
                      const char *what) {
  uint32_t cap = pb_radix_sort_capacity(s);
  uint32_t m = count_word_value < n ? count_word_value : n; /* keys the GPU sorts */
  if (m > cap) m = cap;
  uint32_t *keys = calloc(n ? n : 1, sizeof *keys), *vals = calloc(n ? n : 1, sizeof *vals);
  uint32_t *gk = calloc(m ? m : 1, sizeof *gk), *gv = calloc(m ? m : 1, sizeof *gv);
  pair *ref = calloc(m ? m : 1, sizeof *ref);
  uint32_t mask = bits >= 32 ? 0xffffffffu : ((1u << bits) - 1u);
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t k = urand();
    if (kind == EQUAL) k = 0x2aaaaaaau;
    if (kind == FEW) k = (urand() % 5u) * 0x01234567u;
    if (kind == SORTED) k = i * 37u;
    if (kind == REVERSED) k = (n - i) * 37u;
    keys[i] = k & mask;
    vals[i] = i;
  }
  for (uint32_t i = 0; i < m; ++i) ref[i] = (pair){keys[i], vals[i]};
  qsort(ref, m, sizeof *ref, cmp_pair);

  pb_gpu_buffer count;
  pb_gpu_buffer_desc cd = {.name = "test.count", .size = 16};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &cd, &count), PB_OK);
  uint32_t words[4] = {0xdeadbeefu, 7, 7, count_word_value};
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &count, 0, words, sizeof words), PB_OK);
  uint32_t up = n < cap ? n : cap;
  if (up) {
    CHECK_EQ_INT(pb_gpu_buffer_upload(g, (pb_gpu_buffer *)pb_radix_sort_keys(s), 0, keys, up * 4ull), PB_OK);
    CHECK_EQ_INT(pb_gpu_buffer_upload(g, (pb_gpu_buffer *)pb_radix_sort_vals(s), 0, vals, up * 4ull), PB_OK);
  }
  CHECK_EQ_INT(pb_radix_sort_bind(g, s, &count, 3), PB_OK);
  double t0 = pb_time_now();
  CHECK_EQ_INT(pb_gpu_begin(g), PB_OK);
  pb_gpu_timestamp(g, 0);
  CHECK_EQ_INT(pb_radix_sort_record(g, s), PB_OK);
  pb_gpu_timestamp(g, 1);
  pb_result r = pb_gpu_submit(g);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) fprintf(stderr, "%s: %s\n", what, pb_error_message());
  double ms = pb_gpu_elapsed_ms(g, 0, 1);
  if (ms < 0) ms = (pb_time_now() - t0) * 1e3;
  uint64_t off = pb_radix_sort_result(s) * 4ull;
  if (m) {
    CHECK_EQ_INT(pb_gpu_buffer_download(g, pb_radix_sort_keys(s), off, gk, m * 4ull), PB_OK);
    CHECK_EQ_INT(pb_gpu_buffer_download(g, pb_radix_sort_vals(s), off, gv, m * 4ull), PB_OK);
  }
  uint32_t bad = 0, first_bad = UINT32_MAX;
  for (uint32_t i = 0; i < m; ++i)
    if (gk[i] != ref[i].key || gv[i] != ref[i].val) {
      if (!bad) first_bad = i;
      bad++;
    }
  printf("sort %-28s n=%-8u bits %-2u %s: %u wrong (first %d), %.3f ms (%.2f M keys/s)\n", what, m, bits,
         pb_radix_sort_path_name(pb_radix_sort_get_path(s)), bad, first_bad == UINT32_MAX ? -1 : (int)first_bad,
         ms, ms > 0 ? m / ms / 1e3 : 0.0);
  CHECK_EQ_INT(bad, 0);
  pb_gpu_buffer_destroy(g, &count);
  free(keys), free(vals), free(gk), free(gv), free(ref);
  pb_error_clear();
}

/* digit_bits: the serial path's (0: its default), ignored by the others.
 * full: every case at 30 bits (else a few at 30 bits). */
static void run_path(pb_gpu *g, pb_radix_sort_path path, uint32_t digit_bits, int full) {
  static const struct {
    uint32_t bits;
  } widths[] = {{30}, {32}, {8}, {16}, {24}, {21}};
  for (size_t w = 0; w < sizeof widths / sizeof *widths; ++w) {
    uint32_t bits = widths[w].bits;
    pb_radix_sort_desc d = {.capacity = 4096, .key_bits = bits, .path = path, .digit_bits = digit_bits};
    pb_radix_sort *s = NULL;
    CHECK_EQ_INT(pb_radix_sort_create(g, &d, &s), PB_OK);
    if (!s) return;
    CHECK_EQ_INT(pb_radix_sort_get_path(s), path);
    /* The widths the header promises, counted here apart from the sort. */
    uint32_t db = path != PB_SORT_PATH_SERIAL ? 8u : digit_bits ? digit_bits : 8u;
    if (db > bits) db = bits;
    uint32_t passes = (bits + db - 1) / db;
    CHECK_EQ_INT(pb_radix_sort_digit_bits(s), db);
    CHECK_EQ_INT(pb_radix_sort_passes(s), passes);
    CHECK_EQ_INT(pb_radix_sort_result(s), passes % 2 ? 4096 : 0);
    char what[64];
    snprintf(what, sizeof what, "%u-bit digits, random", db);
    if (bits == 30 && !full) {
      sort_case(g, s, 4096, bits, RANDOM, 4096, what);
      sort_case(g, s, 3001, bits, RANDOM, 3001, what);
      sort_case(g, s, 4000, bits, FEW, 4000, "5 distinct");
      sort_case(g, s, 4000, bits, REVERSED, 4000, "reversed");
      CHECK_EQ_INT(pb_radix_sort_reserve(g, s, 300001), PB_OK);
      sort_case(g, s, 300001, bits, RANDOM, 300001, "grown, 300001");
    } else if (bits == 30) {
      uint32_t sizes[] = {0, 1, 2, 1023, 1024, 1025, 3001, 4096};
      for (size_t i = 0; i < sizeof sizes / sizeof *sizes; ++i) sort_case(g, s, sizes[i], bits, RANDOM, sizes[i], "random");
      sort_case(g, s, 4000, bits, EQUAL, 4000, "all equal");
      sort_case(g, s, 4000, bits, FEW, 4000, "5 distinct");
      sort_case(g, s, 4000, bits, SORTED, 4000, "sorted");
      sort_case(g, s, 4000, bits, REVERSED, 4000, "reversed");
      sort_case(g, s, 4096, bits, RANDOM, 2500, "count word < keys");
      sort_case(g, s, 4096, bits, RANDOM, 1000000, "count word > capacity");
      /* Grown: the same object sorts a larger array after reserve + bind. */
      CHECK_EQ_INT(pb_radix_sort_reserve(g, s, 1500000), PB_OK);
      CHECK_EQ_INT(pb_radix_sort_capacity(s), 1500000);
      sort_case(g, s, 70001, bits, FEW, 70001, "grown, 5 distinct");
      sort_case(g, s, 1500000, bits, RANDOM, 1500000, "grown, 1.5 M");
    } else {
      sort_case(g, s, 4096, bits, RANDOM, 4096, what);
      sort_case(g, s, 3333, bits, FEW, 3333, "5 distinct");
    }
    pb_radix_sort_destroy(g, s);
  }
}

int main(void) {
  PBT_GPU_OPEN(g);
  const pb_gpu_limits *lim = pb_gpu_get_limits(g);
  printf("device %s, %s, subgroup size %u, subgroup ops 0x%x\n", pb_gpu_device_name(g), lim->cpu ? "CPU" : "GPU",
         lim->subgroup_size, lim->subgroup_ops);
  /* The path the sort takes by default: serial on a CPU device. */
  pb_radix_sort *s = NULL;
  CHECK_EQ_INT(pb_radix_sort_create(g, NULL, &s), PB_OK);
  if (s && lim->cpu) CHECK_EQ_INT(pb_radix_sort_get_path(s), PB_SORT_PATH_SERIAL);
  if (s && !lim->cpu) CHECK(pb_radix_sort_get_path(s) != PB_SORT_PATH_SERIAL);
  pb_radix_sort_destroy(g, s);
  /* Digit widths outside the serial path's range are refused. */
  pb_radix_sort_desc bad = {.path = PB_SORT_PATH_SERIAL, .digit_bits = 12};
  s = NULL;
  CHECK(pb_radix_sort_create(g, &bad, &s) != PB_OK);
  CHECK(s == NULL);
  pb_error_clear();
  run_path(g, PB_SORT_PATH_SERIAL, 0, 1);
  run_path(g, PB_SORT_PATH_SERIAL, 9, 0);
  run_path(g, PB_SORT_PATH_SERIAL, 10, 0);
  run_path(g, PB_SORT_PATH_SERIAL, 11, 0);
  /* Where the device has subgroup ballots and shuffles (lavapipe does). */
  const uint32_t need = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_BALLOT_BIT | VK_SUBGROUP_FEATURE_SHUFFLE_BIT;
  if ((lim->subgroup_ops & need) == need && lim->subgroup_size >= 8 && lim->subgroup_size <= 64)
    run_path(g, PB_SORT_PATH_SUBGROUP, 0, 1);
  else
    printf("subgroup path: the device has no subgroups of 8..64 with ballots and shuffles\n");
  run_path(g, PB_SORT_PATH_PORTABLE, 0, 1);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
