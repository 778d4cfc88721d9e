/* The benchmark's fixed leaf-size threshold (pb_photon_estimate_desc.leaf_size,
 * `render --leaf-size`, seed 000 Table 1's sweep) against T_auto on the same
 * photons: with a fixed threshold L every leaf (read back from the nodes)
 * holds at most L photons unless all its photons share one Morton code, the leaf count falls as L grows, every photon is in
 * exactly one leaf, the reported T_auto stays the automatic value (what
 * T_auto would have been) while leaf_size reports L; the radix sort's time is
 * part of the build's. Also the radius histogram of `render --json` is
 * checked in tests/bench.cmake. Exit 77 without a Vulkan device. */
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

static uint64_t rng_state = 777;
static float frand(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (float)((rng_state >> 40) & 0xffffff) / 16777216.0f;
}

typedef struct leaf_stats {
  uint32_t leaves, max_leaf, covered, t_auto, leaf_size, over_without_tie;
  double build_ms, sort_ms;
} leaf_stats;

static void build(pb_gpu *g, const pb_scene *s, const pb_photon_map *map, uint32_t leaf, leaf_stats *out) {
  memset(out, 0, sizeof *out);
  pb_photon_estimate_desc d = {.leaf_size = leaf};
  pb_photon_estimator *e = NULL;
  CHECK_EQ_INT(pb_photon_estimator_create(g, s, &d, &e), PB_OK);
  if (!e) return;
  double ms = -1;
  CHECK_EQ_INT(pb_photon_estimator_build(g, e, map, &ms), PB_OK);
  pb_photon_estimate_stats st;
  CHECK_EQ_INT(pb_photon_estimator_stats(g, e, &st), PB_OK);
  lbvh_host h;
  CHECK(lbvh_download(g, e, &h));
  lbvh_walk w;
  lbvh_walk_tree(&h, &w);
  out->leaves = w.leaves;
  out->max_leaf = w.max_leaf;
  out->covered = h.n - w.not_once;
  out->over_without_tie = w.big_leaf;
  CHECK_EQ_INT(w.not_once, 0);
  CHECK_EQ_INT(w.unmerged, 0);
  lbvh_free(&h);
  out->t_auto = st.t_auto;
  out->leaf_size = st.leaf_size;
  out->build_ms = st.build_ms;
  out->sort_ms = st.sort_ms;
  CHECK_EQ_INT(st.leaves, out->leaves);
  pb_photon_estimator_destroy(g, e);
}

int main(void) {
  PBT_GPU_OPEN(g);
  /* A 10 x 10 m floor; 20000 photons whose footprints cover a point about
   * 12 times (k = 12, T_auto 4). */
  float pos[4][3] = {{-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}};
  uint32_t tri[2][3] = {{0, 1, 2}, {0, 2, 3}}, tm[2] = {0, 0};
  pb_material mat;
  memset(&mat, 0, sizeof mat);
  mat.base_color[3] = 1;
  mat.base_color_tex = mat.metallic_roughness_tex = mat.emissive_tex = mat.normal_tex = PB_NO_TEXTURE;
  pb_scene s;
  memset(&s, 0, sizeof s);
  s.positions = pos;
  s.vertex_count = 4;
  s.triangles = tri;
  s.triangle_material = tm;
  s.triangle_count = 2;
  s.materials = &mat;
  s.material_count = 1;
  const uint32_t n = 20000;
  const float radius = (float)sqrt(12.0 * 100.0 / (M_PI * n));
  pb_gpu_photon *ph = calloc(n, sizeof *ph);
  for (uint32_t i = 0; i < n; ++i) {
    pb_gpu_photon *p = &ph[i];
    /* A tenth of the photons on one point: runs of one Morton code. */
    int tie = i % 10 == 0;
    p->position[0] = tie ? 1.0f : frand() * 10 - 5;
    p->position[2] = tie ? 1.0f : frand() * 10 - 5;
    p->power[0] = p->power[1] = p->power[2] = 1e-3f;
    p->normal[1] = p->wi[1] = 1;
    p->axis_u[0] = radius;
    p->axis_v[2] = radius;
    p->radius = radius;
    p->normal_extent = 0.1f * radius;
    p->path = i;
  }
  pb_photon_map map;
  memset(&map, 0, sizeof map);
  map.capacity = map.stored = n;
  pb_gpu_buffer_desc bd = {.name = "test.photons", .size = (uint64_t)n * sizeof(pb_gpu_photon)};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &bd, &map.photons), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &map.photons, 0, ph, (uint64_t)n * sizeof *ph), PB_OK);

  leaf_stats a, l1, l8, l64, l512;
  build(g, &s, &map, 0, &a);
  build(g, &s, &map, 1, &l1);
  build(g, &s, &map, 8, &l8);
  build(g, &s, &map, 64, &l64);
  build(g, &s, &map, 512, &l512);
  printf("T_auto %u: %u leaves; fixed 1: %u, 8: %u, 64: %u, 512: %u leaves; sort %.2f of %.2f ms\n", a.t_auto,
         a.leaves, l1.leaves, l8.leaves, l64.leaves, l512.leaves, a.sort_ms, a.build_ms);
  /* T_auto from the areas: k = n pi r^2 / 100 m^2 = 12 footprints over a
   * point; the cost model's optimum for k 12 and 20000 photons is 4 (the
   * GPU's float sum may land beside it). */
  CHECK_EQ_INT(lbvh_t_auto_model(12.0, n), 4);
  CHECK(a.t_auto >= 3 && a.t_auto <= 5);
  CHECK_EQ_INT(a.leaf_size, a.t_auto);
  const leaf_stats *fixed[] = {&l1, &l8, &l64, &l512};
  const uint32_t sizes[] = {1, 8, 64, 512};
  for (int i = 0; i < 4; ++i) {
    CHECK_EQ_INT(fixed[i]->t_auto, a.t_auto); /* still the automatic value */
    CHECK_EQ_INT(fixed[i]->leaf_size, sizes[i]);
    CHECK_EQ_INT(fixed[i]->covered, n);       /* every photon in one leaf */
    CHECK_EQ_INT(fixed[i]->over_without_tie, 0);
    if (i > 0) CHECK(fixed[i]->leaves < fixed[i - 1]->leaves);
  }
  CHECK_EQ_INT(a.covered, n);
  /* The tie run (2000 photons on one point) is one leaf whatever L is. */
  CHECK(l1.max_leaf >= n / 10);
  /* With leaves of up to 512, leaves average far above 8. */
  CHECK(l512.leaves * 64 < n);
  CHECK(a.leaves < l1.leaves && a.leaves > l64.leaves);
  /* The sort is timed inside the build. */
  if (a.sort_ms >= 0) CHECK(a.sort_ms > 0 && a.sort_ms <= a.build_ms);

  /* Over the limit: a usage error naming the size, no estimator. */
  pb_photon_estimate_desc bad = {.leaf_size = PB_LBVH_MAX_FIXED_LEAF + 1};
  pb_photon_estimator *e = NULL;
  CHECK_EQ_INT(pb_photon_estimator_create(g, &s, &bad, &e), PB_ERR_USAGE);
  CHECK(e == NULL);
  CHECK(strstr(pb_error_message(), "leaf size 4097") != NULL);
  pb_error_clear();
  pb_photon_map_destroy(g, &map);
  free(ph);
  pb_gpu_destroy(g);
  return pbt_done();
}
