/* Photon LBVH build and radix-sort rates against photon count (not a test;
 * bench/run_bench.py runs it, issue 8 part 3):
 *
 *   pb_bench_lbvh [--device N] [--repeat R] [--k K] COUNT...
 *
 * For each COUNT: that many synthetic photons, uniformly random on a
 * 10 x 10 m floor (the scene T_auto divides by), with skewed elliptic
 * footprints sized so that about K (default 20) footprints cover a point
 * (so T_auto ~ K at every count, as in a real map at a fixed smoothing);
 * the LBVH is built R times (default 3, after one warm-up build that also
 * JIT-compiles the kernels on lavapipe) and the best is kept. Times are GPU
 * timestamps: the whole build (bounds .. leaf merge) and the radix sort
 * alone (8 passes of 4 bits over the 30-bit Morton codes). Prints one JSON
 * object per line:
 *
 *   {"photons": N, "build_ms": .., "sort_ms": .., "build_mphotons_s": ..,
 *    "sort_mkeys_s": .., "t_auto": .., "leaves": .., "device": ".."}
 *
 * or {"photons": N, "error": "..."} when a count does not fit the device
 * (e.g. over maxStorageBufferRange), and goes on with the next count. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "render/photon.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static float frand(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (float)((rng_state >> 40) & 0xffffff) / 16777216.0f;
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
  int first = 1;
  for (; first < argc && argv[first][0] == '-' && argv[first][1] == '-'; first += 2) {
    if (first + 1 >= argc) break;
    if (!strcmp(argv[first], "--device")) gd.device_set = 1, gd.device = (uint32_t)strtoul(argv[first + 1], NULL, 10);
    else if (!strcmp(argv[first], "--repeat")) repeat = (uint32_t)strtoul(argv[first + 1], NULL, 10);
    else if (!strcmp(argv[first], "--k")) k = strtod(argv[first + 1], NULL);
    else break;
  }
  if (first >= argc || repeat == 0 || !(k > 0)) {
    fprintf(stderr, "usage: pb_bench_lbvh [--device N] [--repeat R] [--k K] COUNT...\n");
    return 2;
  }
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
    /* Mean footprint area pi r^2 (skew aside) so that n pi r^2 = K * 100 m^2. */
    float radius = (float)sqrt(k * 100.0 / (M_PI * n));
    pb_photon_estimator *e = NULL;
    pb_photon_map map;
    memset(&map, 0, sizeof map);
    pb_gpu_photon *ph = malloc((size_t)n * sizeof *ph);
    double best = INFINITY, best_sort = INFINITY;
    pb_photon_estimate_stats st;
    memset(&st, 0, sizeof st);
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
      double ms = 0;
      r = pb_photon_estimator_build(g, e, &map, &ms);
      if (r == PB_OK) r = pb_photon_estimator_stats(g, e, &st);
      if (r == PB_OK && i > 0) { /* i = 0: warm-up */
        if (ms < best) best = ms;
        if (st.sort_ms >= 0 && st.sort_ms < best_sort) best_sort = st.sort_ms;
      }
    }
    if (r == PB_OK) {
      printf("{\"photons\": %u, \"build_ms\": %.4f, \"sort_ms\": %.4f, \"build_mphotons_s\": %.4f, "
             "\"sort_mkeys_s\": %.4f, \"t_auto\": %u, \"leaves\": %u, \"repeat\": %u, \"device\": ",
             n, best, isfinite(best_sort) ? best_sort : -1.0, n / best / 1e3,
             isfinite(best_sort) ? n / best_sort / 1e3 : -1.0, st.t_auto, st.leaves, repeat);
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
