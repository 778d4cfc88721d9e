/* Photon LBVH build and radix-sort rates against photon count (not a test;
 * bench/run_bench.py and bench/device_run.sh run it):
 *
 *   pb_bench_lbvh [--device N] [--repeat R] [--k K] [--sort PATH] [--digit-bits B] COUNT...
 *
 * For each COUNT: that many synthetic photons, uniformly random on a
 * 10 x 10 m floor (the scene T_auto divides by), with skewed elliptic
 * footprints sized so that about K (default 20) footprints cover a point
 * (so T_auto ~ K at every count, as in a real map at a fixed smoothing);
 * the LBVH is built R times (default 3, after one warm-up build that also
 * JIT-compiles the kernels on lavapipe) and the best is kept. Then, alone,
 * the radix sort of COUNT random 30-bit keys (uniform over all 30 bits)
 * with their indices (the path
 * PATH: auto, portable, subgroup or serial; default auto, the build's; B:
 * the serial path's digit width, 8..11, default the sort's). Times
 * are GPU timestamps: the whole build and its stages (setup + bounds +
 * T_auto, Morton codes, the sort, the climb: reorder + hierarchy + boxes +
 * leaf merge), and the sort alone. On a CPU device (lavapipe), where the
 * timestamps are wall time and other work on the machine slows them, the
 * process CPU time of each best run is printed too, with the rate it gives
 * on the machine's cores: `*_cpu_mphotons_s` = count / (CPU seconds / cores).
 * One JSON object per line:
 *
 *   {"photons": N, "build_ms": .., "bounds_ms": .., "morton_ms": .., "sort_ms": ..,
 *    "climb_ms": .., "build_cpu_ms": .., "build_mphotons_s": .., "build_cpu_mphotons_s": ..,
 *    "sort_alone_ms": .., "sort_alone_cpu_ms": .., "sort_mkeys_s": .., "sort_cpu_mkeys_s": ..,
 *    "sort_path": "..", "sort_digit_bits": .., "sort_passes": .., "t_auto": .., "leaves": .., "record_bytes": .., "node_bytes": ..,
 *    "cores": .., "device": ".."}
 *
 * (record_bytes: the sorted photon record the gather reads; node_bytes: the
 * tree's share per photon, the (leaves - 1) inner nodes of the merged tree
 * the gather can reach, x sizeof(pb_gpu_lbvh_node) / count), or
 * {"photons": N, "error": "..."} when a count does not fit the device
 * (e.g. over maxStorageBufferRange), and goes on with the next count. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sys/resource.h>
#include <unistd.h>

#include "core/log.h"
#include "render/photon/lbvh_sort.h"
#include "render/photon/photon.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"

#define BENCH_SEED 0x9e3779b97f4a7c15ull
static uint64_t rng_state = BENCH_SEED;
static float frand(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (float)((rng_state >> 40) & 0xffffff) / 16777216.0f;
}

/* Uniform over all 30 bits (frand() * 2^30 had only 24 random bits, the
 * low 6 always 0: the first pass of 8-bit digits met 4 digits, not 256). */
static uint32_t rand30(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (uint32_t)(rng_state >> 34);
}

static void make_photons(pb_gpu_photon *ph, uint32_t n, float radius) {
  for (uint32_t i = 0; i < n; ++i) {
    pb_gpu_photon *p = &ph[i];
    memset(p, 0, sizeof *p);
    p->position[0] = frand() * 10 - 5;
    p->position[1] = frand() * 1e-3f;
    p->position[2] = frand() * 10 - 5;
    p->power[0] = p->power[1] = p->power[2] = 1e-3f;
    p->normal[1] = 1;
    p->wi[1] = 1;
    float r = radius * (0.75f + 0.5f * frand()), sk = 0.4f * (frand() - 0.5f);
    p->axis_u[0] = r, p->axis_u[2] = sk * r;
    p->axis_v[2] = r;
    p->radius = r * 1.2f;
    p->normal_extent = 0.1f * r;
    p->path = i;
  }
}

/* CPU seconds of the whole process (lavapipe's threads included). */
static double cpu_now(void) {
  struct rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/* The radix sort alone: n random 30-bit keys, values 0..n-1, best of
 * `repeat` after a warm-up; GPU and CPU milliseconds. */
static pb_result sort_alone(pb_gpu *g, pb_radix_sort_path path, uint32_t digit_bits, uint32_t n, uint32_t repeat,
                            double *ms, double *cpu_ms, const char **path_name, uint32_t *bits_out,
                            uint32_t *passes_out) {
  pb_radix_sort_desc d = {.capacity = n, .key_bits = PB_LBVH_MORTON_BITS, .path = path, .digit_bits = digit_bits};
  pb_radix_sort *s = NULL;
  pb_gpu_buffer count = {0};
  uint32_t *k = malloc((size_t)n * sizeof *k), *v = malloc((size_t)n * sizeof *v);
  pb_result r = k && v ? pb_radix_sort_create(g, &d, &s) : pb_fail(PB_ERR_NOMEM, "host keys for %u", n);
  pb_gpu_buffer_desc cd = {.name = "bench.count", .size = 4};
  if (r == PB_OK) r = pb_gpu_buffer_create(g, &cd, &count);
  if (r == PB_OK) r = pb_gpu_buffer_upload(g, &count, 0, &n, 4);
  if (r == PB_OK) r = pb_radix_sort_bind(g, s, &count, 0);
  *ms = *cpu_ms = INFINITY;
  for (uint32_t i = 0; i <= repeat && r == PB_OK; ++i) {
    for (uint32_t j = 0; j < n; ++j) k[j] = rand30(), v[j] = j;
    r = pb_gpu_buffer_upload(g, (pb_gpu_buffer *)pb_radix_sort_keys(s), 0, k, (uint64_t)n * 4);
    if (r == PB_OK) r = pb_gpu_buffer_upload(g, (pb_gpu_buffer *)pb_radix_sort_vals(s), 0, v, (uint64_t)n * 4);
    if (r == PB_OK) r = pb_gpu_begin(g);
    if (r != PB_OK) break;
    pb_gpu_timestamp(g, 0);
    r = pb_radix_sort_record(g, s);
    pb_gpu_timestamp(g, 1);
    double c0 = cpu_now();
    pb_result rs = pb_gpu_submit(g);
    double c = (cpu_now() - c0) * 1e3, t = pb_gpu_elapsed_ms(g, 0, 1);
    if (r == PB_OK) r = rs;
    if (r == PB_OK && i > 0 && t >= 0 && t < *ms) *ms = t;
    if (r == PB_OK && i > 0 && c < *cpu_ms) *cpu_ms = c;
  }
  if (s) {
    *path_name = pb_radix_sort_path_name(pb_radix_sort_get_path(s));
    *bits_out = pb_radix_sort_digit_bits(s);
    *passes_out = pb_radix_sort_passes(s);
  }
  pb_gpu_buffer_destroy(g, &count);
  pb_radix_sort_destroy(g, s);
  free(k);
  free(v);
  return r;
}

static void json_string(const char *s) {
  putchar('"');
  for (; *s; ++s) {
    if (*s == '"' || *s == '\\') putchar('\\');
    if ((unsigned char)*s >= 0x20) putchar(*s);
  }
  putchar('"');
}

int main(int argc, char **argv) {
  pb_gpu_desc gd = {0};
  uint32_t repeat = 3;
  double k = 20.0;
  pb_radix_sort_path sort_path = PB_SORT_PATH_AUTO;
  uint32_t digit_bits = 0;
  int first = 1;
  for (; first < argc && argv[first][0] == '-' && argv[first][1] == '-'; first += 2) {
    if (first + 1 >= argc) break;
    if (!strcmp(argv[first], "--device")) gd.device_set = 1, gd.device = (uint32_t)strtoul(argv[first + 1], NULL, 10);
    else if (!strcmp(argv[first], "--repeat")) repeat = (uint32_t)strtoul(argv[first + 1], NULL, 10);
    else if (!strcmp(argv[first], "--k")) k = strtod(argv[first + 1], NULL);
    else if (!strcmp(argv[first], "--digit-bits")) digit_bits = (uint32_t)strtoul(argv[first + 1], NULL, 10);
    else if (!strcmp(argv[first], "--sort")) {
      static const char *names[] = {"auto", "portable", "subgroup", "serial"};
      sort_path = (pb_radix_sort_path)4;
      for (int i = 0; i < 4; ++i)
        if (!strcmp(argv[first + 1], names[i])) sort_path = (pb_radix_sort_path)i;
    } else break;
  }
  if (first >= argc || repeat == 0 || !(k > 0) || sort_path > PB_SORT_PATH_SERIAL) {
    fprintf(stderr, "usage: pb_bench_lbvh [--device N] [--repeat R] [--k K] [--sort auto|portable|subgroup|serial] "
                    "[--digit-bits B] COUNT...\n");
    return 2;
  }
  long cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (cores < 1) cores = 1;
  pb_gpu *g;
  pb_result r = pb_gpu_create(&gd, &g);
  if (r != PB_OK) {
    fprintf(stderr, "pb_bench_lbvh: %s\n", pb_error_message());
    return r == PB_ERR_NO_DEVICE || r == PB_ERR_NOT_AVAILABLE ? 77 : 1;
  }
  /* The floor T_auto divides by: 10 x 10 m, two triangles. */
  float pos[4][3] = {{-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}};
  uint32_t tri[2][3] = {{0, 1, 2}, {0, 2, 3}}, tm[2] = {0, 0};
  pb_material mat;
  memset(&mat, 0, sizeof mat);
  mat.base_color[0] = mat.base_color[1] = mat.base_color[2] = 0.5f;
  mat.base_color[3] = 1;
  mat.base_color_tex = mat.metallic_roughness_tex = mat.emissive_tex = mat.normal_tex = PB_NO_TEXTURE;
  mat.roughness = 1;
  pb_scene s;
  memset(&s, 0, sizeof s);
  s.positions = pos;
  s.vertex_count = 4;
  s.triangles = tri;
  s.triangle_material = tm;
  s.triangle_count = 2;
  s.materials = &mat;
  s.material_count = 1;
  int status = 0;
  for (int a = first; a < argc; ++a) {
    double nd = strtod(argv[a], NULL);
    if (!(nd >= 1 && nd <= 4e9)) {
      fprintf(stderr, "pb_bench_lbvh: bad count %s\n", argv[a]);
      status = 2;
      continue;
    }
    uint32_t n = (uint32_t)nd;
    rng_state = BENCH_SEED; /* the same photons for a count whatever ran before */
    /* Mean footprint area pi r^2 (skew aside) so that n pi r^2 = K * 100 m^2. */
    float radius = (float)sqrt(k * 100.0 / (M_PI * n));
    pb_photon_estimator *e = NULL;
    pb_photon_map map;
    memset(&map, 0, sizeof map);
    pb_gpu_photon *ph = malloc((size_t)n * sizeof *ph);
    double best = INFINITY, best_cpu = INFINITY;
    pb_photon_estimate_stats st, bst;
    memset(&st, 0, sizeof st);
    memset(&bst, 0, sizeof bst);
    if (!ph) r = pb_fail(PB_ERR_NOMEM, "host copy of %u photons", n);
    else r = pb_photon_estimator_create(g, &s, NULL, &e);
    if (r == PB_OK) {
      make_photons(ph, n, radius);
      map.capacity = n;
      pb_gpu_buffer_desc bd = {.name = "bench.photons", .size = (uint64_t)n * sizeof(pb_gpu_photon)};
      r = pb_gpu_buffer_create(g, &bd, &map.photons);
      if (r == PB_OK) r = pb_gpu_buffer_upload(g, &map.photons, 0, ph, (uint64_t)n * sizeof *ph);
      map.stored = n;
    }
    for (uint32_t i = 0; i <= repeat && r == PB_OK; ++i) {
      double ms = 0, c0 = cpu_now();
      r = pb_photon_estimator_build(g, e, &map, &ms);
      double cpu = (cpu_now() - c0) * 1e3;
      if (r == PB_OK) r = pb_photon_estimator_stats(g, e, &st);
      if (r == PB_OK && i > 0) { /* i = 0: warm-up */
        if (ms < best) best = ms, bst = st;
        if (cpu < best_cpu) best_cpu = cpu;
      }
    }
    double sort_ms = -1, sort_cpu = -1;
    const char *sort_name = "?";
    uint32_t sort_bits = 0, sort_passes = 0;
    if (r == PB_OK)
      r = sort_alone(g, sort_path, digit_bits, n, repeat, &sort_ms, &sort_cpu, &sort_name, &sort_bits, &sort_passes);
    if (r == PB_OK) {
      /* The gather's bytes per photon: its record, and the nodes it can reach
       * (the merged tree's leaves - 1 inner nodes). */
      double node_bytes = bst.leaves > 1 ? (double)(bst.leaves - 1) * sizeof(pb_gpu_lbvh_node) / n
                                         : (double)sizeof(pb_gpu_lbvh_node) / n;
      printf("{\"photons\": %u, \"build_ms\": %.4f, \"bounds_ms\": %.4f, \"morton_ms\": %.4f, \"sort_ms\": %.4f, "
             "\"climb_ms\": %.4f, \"build_cpu_ms\": %.4f, \"build_mphotons_s\": %.4f, \"build_cpu_mphotons_s\": %.4f, "
             "\"sort_alone_ms\": %.4f, \"sort_alone_cpu_ms\": %.4f, \"sort_mkeys_s\": %.4f, "
             "\"sort_cpu_mkeys_s\": %.4f, \"sort_path\": \"%s\", \"sort_digit_bits\": %u, \"sort_passes\": %u, "
             "\"t_auto\": %u, \"leaves\": %u, "
             "\"record_bytes\": %u, \"node_bytes\": %.2f, \"repeat\": %u, \"cores\": %ld, \"device\": ",
             n, best, bst.bounds_ms, bst.morton_ms, bst.sort_ms, bst.climb_ms, best_cpu, n / best / 1e3,
             n / (best_cpu / cores) / 1e3, sort_ms, sort_cpu, n / sort_ms / 1e3, n / (sort_cpu / cores) / 1e3,
             sort_name, sort_bits, sort_passes, bst.t_auto, bst.leaves, (unsigned)sizeof(pb_gpu_photon_packed), node_bytes, repeat, cores);
      json_string(pb_gpu_device_name(g));
      printf("}\n");
    } else {
      printf("{\"photons\": %u, \"error\": ", n);
      json_string(pb_error_message());
      printf("}\n");
      pb_error_clear();
      status = 1;
    }
    fflush(stdout);
    free(ph);
    pb_photon_map_destroy(g, &map);
    pb_photon_estimator_destroy(g, e);
  }
  pb_gpu_destroy(g);
  return status;
}
