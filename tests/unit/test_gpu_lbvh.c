/* The photon LBVH built on the GPU (src/render/lbvh.c), checked
 * structurally on the host: sorted Morton order, the photons a permutation
 * of the input, every photon reached exactly once by the gather's traversal
 * rules (leaf references run to PB_PHOTON_LEAF_END), every inner node's box
 * containing its children's boxes and the exact ellipsoid AABBs of all its
 * photons, leaves no larger than T_auto unless they are a run of one Morton
 * code, T_auto = round(footprint area sum / scene area). Cases: random
 * photons with skewed footprints, all photons at one position (identical
 * codes), one photon, two photons, zero photons, 10^7 photons. Validation layers on, any
 * message fatal; exit 77 without a Vulkan device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "render/photon.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"

static uint64_t rng_state = 12345;
static float frand(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (float)((rng_state >> 40) & 0xffffff) / 16777216.0f;
}

static void photon_box(const pb_gpu_photon *p, float lo[3], float hi[3]) {
  for (int k = 0; k < 3; ++k) {
    float w = p->normal[k] * p->normal_extent;
    float e = sqrtf(p->axis_u[k] * p->axis_u[k] + p->axis_v[k] * p->axis_v[k] + w * w);
    lo[k] = p->position[k] - e;
    hi[k] = p->position[k] + e;
  }
}

static int contains(const float lo[3], const float hi[3], const float l2[3], const float h2[3]) {
  for (int k = 0; k < 3; ++k) {
    float tol = 1e-5f * (1.0f + fabsf(lo[k]) + fabsf(hi[k]));
    if (l2[k] < lo[k] - tol || h2[k] > hi[k] + tol) return 0;
  }
  return 1;
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

/* mode 0: random; 1: all at one point; 2: clustered on a few points. */
static void make_photons(pb_gpu_photon *ph, uint32_t n, int mode, float radius) {
  for (uint32_t i = 0; i < n; ++i) {
    pb_gpu_photon *p = &ph[i];
    memset(p, 0, sizeof *p);
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
    p->path = i; /* identity for the permutation check */
  }
}

static void check_case(pb_gpu *g, pb_photon_estimator *e, uint32_t n, int mode, float radius, const char *what) {
  pb_gpu_photon *ph = calloc(n ? n : 1, sizeof *ph);
  make_photons(ph, n, mode, radius);
  pb_photon_map map;
  memset(&map, 0, sizeof map);
  map.capacity = n ? n : 1;
  pb_gpu_buffer_desc bd = {.name = "test.photons", .size = (uint64_t)map.capacity * sizeof(pb_gpu_photon)};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &bd, &map.photons), PB_OK);
  if (n) CHECK_EQ_INT(pb_gpu_buffer_upload(g, &map.photons, 0, ph, (uint64_t)n * sizeof *ph), PB_OK);
  map.stored = n;
  double ms = -1;
  pb_result r = pb_photon_estimator_build(g, e, &map, &ms);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) fprintf(stderr, "%s: %s\n", what, pb_error_message());
  pb_photon_estimate_stats st;
  CHECK_EQ_INT(pb_photon_estimator_stats(g, e, &st), PB_OK);
  pb_photon_lbvh_view v;
  pb_photon_estimator_lbvh(e, &v);
  CHECK_EQ_INT(v.count, n);
  pb_gpu_lbvh_info info;
  CHECK_EQ_INT(pb_gpu_buffer_download(g, v.info, 0, &info, sizeof info), PB_OK);
  uint32_t nodes_n = n > 1 ? n - 1 : 0;
  pb_gpu_lbvh_node *nodes = calloc(nodes_n ? nodes_n : 1, sizeof *nodes);
  pb_gpu_photon *sp = calloc(n ? n : 1, sizeof *sp);
  uint32_t *keys = calloc(n ? n : 1, sizeof *keys);
  uint32_t *seen = calloc(n ? n : 1, sizeof *seen);
  if (n) {
    CHECK_EQ_INT(pb_gpu_buffer_download(g, v.photons, 0, sp, (uint64_t)n * sizeof *sp), PB_OK);
    CHECK_EQ_INT(pb_gpu_buffer_download(g, v.keys, 0, keys, (uint64_t)n * sizeof *keys), PB_OK);
  }
  if (nodes_n) CHECK_EQ_INT(pb_gpu_buffer_download(g, v.nodes, 0, nodes, (uint64_t)nodes_n * sizeof *nodes), PB_OK);
  /* T_auto from the footprint areas. */
  double area = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const float *u = ph[i].axis_u, *w = ph[i].axis_v;
    double c[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    area += M_PI * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  }
  double ratio = area / 100.0;
  uint32_t t_want = ratio < 1 ? 1 : (ratio > 256 ? 256 : (uint32_t)floor(ratio + 0.5));
  CHECK_NEAR(info.area_sum, area, 1e-3 * area + 1e-9);
  if (n) {
    CHECK((int)info.t_auto >= (int)t_want - 1 && info.t_auto <= t_want + 1); /* float sum rounding */
  }
  /* Sorted codes; the photons a permutation of the input. */
  uint32_t unsorted = 0, perm_bad = 0;
  for (uint32_t i = 1; i < n; ++i) unsorted += keys[i] < keys[i - 1];
  for (uint32_t i = 0; i < n; ++i) {
    if (sp[i].path >= n || seen[sp[i].path]++) perm_bad++;
    else if (memcmp(sp[i].position, ph[sp[i].path].position, sizeof sp[i].position)) perm_bad++;
  }
  CHECK_EQ_INT(unsorted, 0);
  CHECK_EQ_INT(perm_bad, 0);
  /* Traversal as the gather does it: every photon exactly once; leaf sizes. */
  memset(seen, 0, (n ? n : 1) * sizeof *seen);
  uint32_t stack[PB_LBVH_STACK * 4], sp_n = 0, big_leaves = 0, overflow = 0, leaves = 0, max_leaf = 0;
  if (n) stack[sp_n++] = info.root;
  else CHECK_EQ_INT(info.root, PB_LBVH_NONE);
  uint32_t box_bad = 0, inner = 0;
  while (sp_n) {
    uint32_t ref = stack[--sp_n];
    if (ref & PB_LBVH_LEAF) {
      uint32_t i = ref & ~PB_LBVH_LEAF, first = i;
      for (; i < n; ++i) {
        seen[i]++;
        if (sp[i].flags & PB_PHOTON_LEAF_END) break;
      }
      if (i >= n) overflow++, i = n - 1;
      uint32_t size = i - first + 1;
      leaves++;
      if (size > max_leaf) max_leaf = size;
      if (size > info.t_auto && keys[first] != keys[i]) big_leaves++;
      continue;
    }
    if (ref >= nodes_n) {
      box_bad++;
      continue;
    }
    const pb_gpu_lbvh_node *nd = &nodes[ref];
    inner++;
    for (uint32_t i = nd->first; i <= nd->last && i < n; ++i) {
      float lo[3], hi[3];
      photon_box(&sp[i], lo, hi);
      if (!contains(nd->lo, nd->hi, lo, hi)) {
        if (box_bad < 3)
          printf("node %u [%u,%u] box %g %g %g - %g %g %g photon %u box %g %g %g - %g %g %g\n", ref, nd->first, nd->last,
                 nd->lo[0], nd->lo[1], nd->lo[2], nd->hi[0], nd->hi[1], nd->hi[2], i, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
        box_bad++;
      }
    }
    const uint32_t ch[2] = {nd->left, nd->right};
    for (int k = 0; k < 2; ++k) {
      if (!(ch[k] & PB_LBVH_LEAF)) {
        if (ch[k] >= nodes_n || !contains(nd->lo, nd->hi, nodes[ch[k]].lo, nodes[ch[k]].hi) ||
            nodes[ch[k]].parent != ref)
          box_bad++;
      }
      if (sp_n < sizeof stack / sizeof *stack) stack[sp_n++] = ch[k];
      else overflow++;
    }
  }
  uint32_t reached_bad = 0;
  for (uint32_t i = 0; i < n; ++i) reached_bad += seen[i] != 1;
  printf("lbvh %-22s n=%-6u T_auto %-3u (area ratio %.2f) leaves %u (info %u, largest %u), inner reached %u, "
         "build %.2f ms\n",
         what, n, info.t_auto, ratio, leaves, info.leaves, max_leaf, inner, ms);
  CHECK_EQ_INT(reached_bad, 0);
  CHECK_EQ_INT(box_bad, 0);
  CHECK_EQ_INT(big_leaves, 0);
  CHECK_EQ_INT(overflow, 0);
  CHECK_EQ_INT(leaves, info.leaves);
  CHECK_EQ_INT(st.t_auto, info.t_auto);
  if (mode == 1 && n) CHECK_EQ_INT(leaves, 1); /* one Morton code: one leaf */
  free(nodes);
  free(sp);
  free(keys);
  free(seen);
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
    check_case(g, e, 5000, 0, 0.02f, "random, small");   /* T_auto 1 */
    check_case(g, e, 3000, 0, 0.3f, "random, large");    /* T_auto > 1 */
    check_case(g, e, 300, 1, 0.05f, "identical codes");
    check_case(g, e, 97, 2, 0.05f, "three clusters");
    check_case(g, e, 2, 0, 0.05f, "two photons");
    check_case(g, e, 1, 0, 0.05f, "one photon");
    check_case(g, e, 0, 0, 0.05f, "zero photons");
    check_case(g, e, 20000, 0, 0.05f, "random, after empty"); /* buffers grow */
    /* Over 65535 photons: llvmpipe ends an invocation's loops after 65535
     * iterations in all, which cut the root's box short when one invocation
     * looped over the whole map (the gather then lost the x > 0 half). */
    check_case(g, e, 100000, 0, 0.02f, "random, > 65535");
    /* Ten million (issue 9): 960 MB of records, every structural check, on a
     * device whose storage buffers can hold them (NVIDIA: 4 GiB). lavapipe's
     * maxStorageBufferRange is 128 MiB: there the largest map that fits
     * (1.4 M photons) is checked, and the 10^7 map must fail cleanly with
     * PB_ERR_LIMIT naming the buffer, never be truncated. */
    uint64_t range = pb_gpu_get_limits(g)->max_storage_buffer_range;
    uint64_t fit = range / sizeof(pb_gpu_photon);
    if (fit >= 10000000) {
      check_case(g, e, 10000000, 0, 0.001f, "random, 10^7");
    } else {
      printf("lbvh: 10^7 photons need %llu MiB storage buffers, the device allows %llu MiB: checking %llu\n",
             (unsigned long long)(10000000ull * sizeof(pb_gpu_photon) >> 20), (unsigned long long)(range >> 20),
             (unsigned long long)fit);
      check_case(g, e, (uint32_t)fit, 0, 0.001f, "random, largest map");
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
