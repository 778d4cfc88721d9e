/* The photon LBVH built on the GPU (src/render/photon/lbvh.c), checked
 * structurally on the host (lbvh_walk.h): sorted Morton order, the photons
 * a permutation of the input (each the record of the map index the sort
 * returned), every photon reached exactly once by the gather's traversal
 * rules, every child's box containing the exact ellipsoid AABBs of all its
 * photons and its children's boxes, children's photon ranges tiling their
 * parent's (inner node p at the split after photon p, where the range's
 * keys first differ: the radix tree's split), leaves no larger than
 * T_auto unless they are a run of one Morton code, and the merge complete (no
 * inner node left that should have been a leaf), depth within the gather's
 * stack, T_auto = round(footprint area sum / scene area). The photon count
 * comes from the map's counts buffer on the GPU (the tracer's maps) or from
 * the host; a counts word over the capacity is clamped. Cases: random photons
 * with skewed footprints, all photons at one position (identical codes),
 * one photon, two photons, zero photons, 10^7 photons. Validation layers on,
 * any message fatal; exit 77 without a Vulkan device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "lbvh_walk.h"
#include "render/photon/photon.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"

static uint64_t rng_state = 12345;
static float frand(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (float)((rng_state >> 40) & 0xffffff) / 16777216.0f;
}

/* A 10 x 10 m floor: the scene whose area T_auto divides by. */
static pb_scene floor_scene(float (*pos)[3], uint32_t (*tri)[3], uint32_t *tm, pb_material *mat) {
  const float q[4][3] = {{-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}};
  memcpy(pos, q, sizeof q);
  tri[0][0] = 0, tri[0][1] = 1, tri[0][2] = 2;
  tri[1][0] = 0, tri[1][1] = 2, tri[1][2] = 3;
  tm[0] = tm[1] = 0;
  memset(mat, 0, sizeof *mat);
  mat->base_color[0] = mat->base_color[1] = mat->base_color[2] = 0.5f;
  mat->base_color[3] = 1;
  mat->base_color_tex = mat->metallic_roughness_tex = mat->emissive_tex = mat->normal_tex = PB_NO_TEXTURE;
  mat->roughness = 1;
  pb_scene s;
  memset(&s, 0, sizeof s);
  s.positions = pos;
  s.vertex_count = 4;
  s.triangles = tri;
  s.triangle_material = tm;
  s.triangle_count = 2;
  s.materials = mat;
  s.material_count = 1;
  return s;
}

/* A random unit vector. */
static void rand_dir(float d[3]) {
  for (;;) {
    float v[3] = {frand() * 2 - 1, frand() * 2 - 1, frand() * 2 - 1};
    float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0.1f && l <= 1.0f) {
      for (int k = 0; k < 3; ++k) d[k] = v[k] / l;
      return;
    }
  }
}

/* mode 0: random; 1: all at one point; 2: clustered on a few points; 3: as
 * 0 with random orientations (normal, wi in its hemisphere, the footprint
 * in its tangent plane) and flags (the packed record's every octant). */
static void make_photons(pb_gpu_photon *ph, uint32_t n, int mode, float radius) {
  for (uint32_t i = 0; i < n; ++i) {
    pb_gpu_photon *p = &ph[i];
    memset(p, 0, sizeof *p);
    if (mode == 3) {
      p->position[0] = frand() * 8 - 4, p->position[1] = frand() * 0.01f, p->position[2] = frand() * 8 - 4;
      p->power[0] = 1e-3f * frand(), p->power[1] = 2e-9f * frand(), p->power[2] = 5.0f * frand();
      float *nn = p->normal, t[3], b[3];
      rand_dir(nn);
      rand_dir(p->wi);
      float c = p->wi[0] * nn[0] + p->wi[1] * nn[1] + p->wi[2] * nn[2];
      if (c < 0)
        for (int k = 0; k < 3; ++k) p->wi[k] = -p->wi[k];
      pb_basis_any(nn, t, b); /* any in-plane frame will do */
      float r = radius * (0.5f + frand()), sk = frand() - 0.5f, rv = r * (0.3f + frand());
      for (int k = 0; k < 3; ++k) p->axis_u[k] = r * t[k] + sk * r * b[k], p->axis_v[k] = rv * b[k];
      p->radius = r * 1.5f;
      p->normal_extent = 0.1f * r;
      p->flags = (i & 1u) | ((i % 100u) << PB_PHOTON_BOUNCE_SHIFT);
      continue;
    }
    float x = mode == 1 ? 0.25f : (mode == 2 ? (float)(i % 3) : frand() * 8 - 4);
    float z = mode == 1 ? -0.5f : (mode == 2 ? 1.0f : frand() * 8 - 4);
    p->position[0] = x, p->position[1] = mode == 0 ? frand() * 0.01f : 0.0f, p->position[2] = z;
    p->power[0] = p->power[1] = p->power[2] = 1e-3f;
    p->normal[1] = 1;
    p->wi[1] = 1;
    float r = radius * (0.5f + frand());
    float sk = frand() - 0.5f;
    p->axis_u[0] = r, p->axis_u[2] = sk * r;
    p->axis_v[2] = r * (0.3f + frand());
    p->radius = r * 1.5f;
    p->normal_extent = 0.1f * r;
  }
}

/* counts: 0: the host's count (map.stored); else the count goes through a
 * pb_gpu_photon_counts buffer holding `counts` stored photons (clamped by
 * the build to the map's capacity n). */
static void check_case(pb_gpu *g, pb_photon_estimator *e, uint32_t n, int mode, float radius, uint32_t counts,
                       const char *what) {
  pb_gpu_photon *ph = calloc(n ? n : 1, sizeof *ph);
  make_photons(ph, n, mode, radius);
  pb_photon_map map;
  memset(&map, 0, sizeof map);
  map.capacity = n ? n : 1;
  pb_gpu_buffer_desc bd = {.name = "test.photons", .size = (uint64_t)map.capacity * sizeof(pb_gpu_photon)};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &bd, &map.photons), PB_OK);
  if (n) CHECK_EQ_INT(pb_gpu_buffer_upload(g, &map.photons, 0, ph, (uint64_t)n * sizeof *ph), PB_OK);
  if (counts) {
    pb_gpu_buffer_desc cd = {.name = "test.counts", .size = sizeof(pb_gpu_photon_counts)};
    pb_gpu_photon_counts c = {.stored = counts};
    CHECK_EQ_INT(pb_gpu_buffer_create(g, &cd, &map.counts), PB_OK);
    CHECK_EQ_INT(pb_gpu_buffer_upload(g, &map.counts, 0, &c, sizeof c), PB_OK);
    map.stored = 0xdeadbeefu; /* never read when the map has its counts on the device */
  } else {
    map.stored = n;
  }
  double ms = -1;
  pb_result r = pb_photon_estimator_build(g, e, &map, &ms);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) fprintf(stderr, "%s: %s\n", what, pb_error_message());
  pb_photon_estimate_stats st;
  CHECK_EQ_INT(pb_photon_estimator_stats(g, e, &st), PB_OK);
  lbvh_host h;
  CHECK(lbvh_download(g, e, &h));
  CHECK_EQ_INT(h.n, n);
  CHECK_EQ_INT(st.photons, n);
  /* T_auto from the footprint areas (the cost model's optimum). */
  double area = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const float *u = ph[i].axis_u, *w = ph[i].axis_v;
    double c[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    area += M_PI * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  }
  double ratio = area / 100.0;
  uint32_t t_want = lbvh_t_auto_model(ratio, n);
  CHECK_NEAR(h.info.area_sum, area, 1e-3 * area + 1e-9);
  if (n) {
    CHECK((int)h.info.t_auto >= (int)t_want - 1 && h.info.t_auto <= t_want + 1); /* float sum rounding */
  }
  /* Sorted codes; the photons a permutation of the input, each the record of
   * the index the sort carried, packed (shared/pb_photon.h,
   * pb_gpu_photon_packed): position, power, normal extent and flags exact,
   * the normal within 1e-4, wi within 2e-3, the axes within 1e-4 of the
   * scale (a record's worst errors; the input's footprints lie in its
   * tangent plane, as the tracer's do). */
  uint32_t unsorted = 0, perm_bad = 0, pack_bad = 0;
  double worst_n = 0, worst_wi = 0, worst_ax = 0;
  uint32_t *seen = calloc(n ? n : 1, sizeof *seen);
  for (uint32_t i = 1; i < n; ++i) unsorted += h.keys[i] < h.keys[i - 1];
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t o = h.order[i];
    if (o >= n || seen[o]++) {
      perm_bad++;
      continue;
    }
    const pb_gpu_photon *a = &h.photons[i], *b = &ph[o];
    if (memcmp(a->position, b->position, sizeof b->position) || memcmp(a->power, b->power, sizeof b->power) ||
        a->normal_extent != b->normal_extent || a->flags != b->flags)
      pack_bad++;
    double s = fmax(b->radius, 1e-30);
    for (int k = 0; k < 3; ++k) {
      worst_n = fmax(worst_n, fabs(a->normal[k] - b->normal[k]));
      worst_wi = fmax(worst_wi, fabs(a->wi[k] - b->wi[k]));
      worst_ax = fmax(worst_ax, fmax(fabs(a->axis_u[k] - b->axis_u[k]), fabs(a->axis_v[k] - b->axis_v[k])) / s);
    }
  }
  CHECK_EQ_INT(unsorted, 0);
  CHECK_EQ_INT(perm_bad, 0);
  CHECK_EQ_INT(pack_bad, 0);
  CHECK(worst_n <= 1e-4);
  CHECK(worst_wi <= 2e-3);
  CHECK(worst_ax <= 1e-4);
  if (worst_n > 1e-4 || worst_wi > 2e-3 || worst_ax > 1e-4)
    fprintf(stderr, "%s: packed record errors: normal %.3g, wi %.3g, axes %.3g of the scale\n", what, worst_n,
            worst_wi, worst_ax);
  lbvh_walk w;
  lbvh_walk_tree(&h, &w);
  printf("lbvh %-26s n=%-8u T_auto %-3u (area ratio %.2f) leaves %u (info %u, largest %u), inner %u, "
         "build %.2f ms (bounds %.2f, morton %.2f, sort %.2f, climb %.2f)\n",
         what, n, h.info.t_auto, ratio, w.leaves, h.info.leaves, w.max_leaf, w.inner, ms, st.bounds_ms,
         st.morton_ms, st.sort_ms, st.climb_ms);
  CHECK_EQ_INT(w.not_once, 0);
  CHECK_EQ_INT(w.box, 0);
  CHECK_EQ_INT(w.range, 0);
  CHECK_EQ_INT(w.big_leaf, 0);
  CHECK_EQ_INT(w.unmerged, 0);
  CHECK_EQ_INT(w.bad_ref, 0);
  CHECK_EQ_INT(w.deep, 0);
  CHECK_EQ_INT(w.split, 0);
  CHECK_EQ_INT(w.leaves, h.info.leaves);
  CHECK_EQ_INT(st.t_auto, h.info.t_auto);
  if (mode == 1 && n) CHECK_EQ_INT(w.leaves, 1); /* one Morton code: one leaf */
  free(seen);
  lbvh_free(&h);
  free(ph);
  pb_photon_map_destroy(g, &map);
  pb_error_clear();
}

int main(void) {
  PBT_GPU_OPEN(g);
  float pos[4][3];
  uint32_t tri[2][3], tm[2];
  pb_material mat;
  pb_scene s = floor_scene(pos, tri, tm, &mat);
  pb_photon_estimator *e = NULL;
  r = pb_photon_estimator_create(g, &s, NULL, &e);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK) {
    check_case(g, e, 5000, 0, 0.02f, 0, "random, small");   /* T_auto 1 */
    check_case(g, e, 3000, 0, 0.3f, 0, "random, large");    /* T_auto > 1 */
    check_case(g, e, 300, 1, 0.05f, 0, "identical codes");
    check_case(g, e, 97, 2, 0.05f, 0, "three clusters");
    check_case(g, e, 4000, 3, 0.05f, 0, "random orientations");
    check_case(g, e, 2, 0, 0.05f, 0, "two photons");
    check_case(g, e, 1, 0, 0.05f, 0, "one photon");
    check_case(g, e, 0, 0, 0.05f, 0, "zero photons");
    check_case(g, e, 20000, 0, 0.05f, 0, "random, after empty"); /* buffers grow */
    /* The count read on the GPU from the map's counts, as the tracer's maps
     * have it; a count over the capacity is clamped to it. */
    check_case(g, e, 4321, 0, 0.05f, 4321, "count from the map");
    check_case(g, e, 777, 0, 0.05f, 100000, "map count over capacity");
    /* Over 65535 photons: llvmpipe ends an invocation's loops after 65535
     * iterations in all, which cut the root's box short when one invocation
     * looped over the whole map (the gather then lost the x > 0 half). */
    check_case(g, e, 100000, 0, 0.02f, 0, "random, > 65535");
    /* Ten million: 960 MB of records, every structural check, on a
     * device whose storage buffers can hold them (NVIDIA: 4 GiB). lavapipe's
     * maxStorageBufferRange is 128 MiB: there the largest map that fits
     * (1.4 M photons) is checked, and the 10^7 map must fail cleanly with
     * PB_ERR_LIMIT naming the buffer, never be truncated. */
    uint64_t range = pb_gpu_get_limits(g)->max_storage_buffer_range;
    uint64_t fit = range / sizeof(pb_gpu_photon);
    if (fit >= 10000000) {
      check_case(g, e, 10000000, 0, 0.001f, 0, "random, 10^7");
    } else {
      printf("lbvh: 10^7 photons need %llu MiB storage buffers, the device allows %llu MiB: checking %llu\n",
             (unsigned long long)(10000000ull * sizeof(pb_gpu_photon) >> 20), (unsigned long long)(range >> 20),
             (unsigned long long)fit);
      check_case(g, e, (uint32_t)fit, 0, 0.001f, 0, "random, largest map");
      pb_gpu_buffer b;
      pb_gpu_buffer_desc bd = {.name = "photons", .size = 10000000ull * sizeof(pb_gpu_photon)};
      CHECK_EQ_INT(pb_gpu_buffer_create(g, &bd, &b), PB_ERR_LIMIT);
      CHECK(strstr(pb_error_message(), "photons") != NULL);
      pb_error_clear();
    }
  }
  pb_photon_estimator_destroy(g, e);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
