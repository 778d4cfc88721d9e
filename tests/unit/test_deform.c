/* Skins and morph targets (glTF 2.0 3.7.3, 3.7.2.2): hand-written glTF
 * files (buffers as data URIs) loaded and posed with pb_scene_set_time,
 * every vertex checked against values worked out by hand:
 *   - a morphed quad: mesh.weights and node.weights at load, a sparse target
 *     without a bufferView, NORMAL targets (normals n + sum w dN,
 *     renormalised), TANGENT targets on a normal-mapped quad, LINEAR and
 *     CUBICSPLINE "weights" channels, the pose at
 *     the file's weights equal to the static load byte for byte;
 *   - a skinned strip of two joints: the static load already posed by a
 *     rotated joint (no animation), the joint animated (slerp), the skinned
 *     node's own transform ignored, normals by the skin matrix, two
 *     JOINTS/WEIGHTS sets, weights that do not sum to 1 rescaled (warned), a
 *     vertex without weight following its mesh node (warned);
 *   - what a static scene pays: no anim, no per-frame data. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "pbtest.h"
#include "gltf_test.h"
#include "scene/scene.h"

static char dir[] = "/tmp/pbtest_deform_XXXXXX";

typedef struct doc {
  uint8_t data[16384];
  size_t n;
  char views[8192], accs[8192];
  int count, view_count;
} doc;

enum { F32 = 5126, U8 = 5121, U16 = 5123 };

/* A bufferView of `bytes` (4-byte aligned), returns its index. */
static int view(doc *g, const void *bytes, size_t nbytes) {
  g->n = (g->n + 3) & ~(size_t)3;
  memcpy(g->data + g->n, bytes, nbytes);
  size_t lv = strlen(g->views);
  snprintf(g->views + lv, sizeof g->views - lv, "%s{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}",
           g->view_count ? "," : "", g->n, nbytes);
  g->n += nbytes;
  return g->view_count++;
}

/* An accessor; bv < 0: none. `more`: extra JSON members ("" for none). */
static int accessor(doc *g, int bv, int ct, size_t count, const char *type, const char *more) {
  size_t la = strlen(g->accs);
  char v[32] = "";
  if (bv >= 0) snprintf(v, sizeof v, "\"bufferView\":%d,", bv);
  snprintf(g->accs + la, sizeof g->accs - la, "%s{%s\"componentType\":%d,\"count\":%zu,\"type\":\"%s\"%s%s}",
           g->count ? "," : "", v, ct, count, type, more[0] ? "," : "", more);
  return g->count++;
}

static int floats(doc *g, const float *v, size_t count, const char *type) {
  int comps = !strcmp(type, "SCALAR") ? 1 : !strcmp(type, "VEC3") ? 3 : !strcmp(type, "VEC4") ? 4 : 16;
  char mm[256] = "";
  if (comps == 3) {
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < count; ++i)
      for (int k = 0; k < 3; ++k) lo[k] = fminf(lo[k], v[i * 3 + k]), hi[k] = fmaxf(hi[k], v[i * 3 + k]);
    snprintf(mm, sizeof mm, "\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  }
  return accessor(g, view(g, v, count * (size_t)comps * 4), F32, count, type, mm);
}

static const pb_load_desc *load_desc; /* NULL: the defaults */

static pb_result load(doc *g, const char *body, pb_scene *s) {
  char *data = pbt_b64(g->data, g->n);
  char path[256];
  snprintf(path, sizeof path, "%s/d.gltf", dir);
  FILE *f = fopen(path, "w");
  fprintf(f,
          "{\"asset\":{\"version\":\"2.0\"},"
          "\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,%s\",\"byteLength\":%zu}],"
          "\"bufferViews\":[%s],\"accessors\":[%s],%s}",
          data, g->n, g->views, g->accs, body);
  fclose(f);
  free(data);
  pb_error_clear();
  pb_result r = pb_scene_load(path, load_desc, s);
  unlink(path);
  return r;
}

static void check_vec(const float *v, double x, double y, double z, double tol, int line) {
  int ok = fabs(v[0] - x) <= tol && fabs(v[1] - y) <= tol && fabs(v[2] - z) <= tol;
  if (!ok) fprintf(stderr, "line %d: (%.9g %.9g %.9g) != (%g %g %g)\n", line, v[0], v[1], v[2], x, y, z);
  CHECK(ok);
}
#define VEC(v, x, y, z) check_vec(v, x, y, z, 1e-5, __LINE__)

static int has_warning(const pb_scene *s, const char *sub) {
  for (uint32_t i = 0; i < s->warning_count; ++i)
    if (strstr(s->warnings[i], sub)) return 1;
  fprintf(stderr, "no warning containing '%s'\n", sub);
  return 0;
}

/* ---- morph targets ---------------------------------------------------------
 * The quad (0,0,0) (1,0,0) (1,1,0) (0,1,0), normals +Z. Target 0 lifts
 * vertices 2 and 3 by z = 1 and turns the normal to (0,-1,1)/sqrt2 (its
 * NORMAL delta); target 1, a sparse accessor without a bufferView, moves
 * vertex 1 by x = 2. mesh.weights [0.5, 0]; node 1 overrides them with [1, 1]. */

static const float quad_pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static const float quad_nrm[12] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
static const uint16_t quad_idx[6] = {0, 1, 2, 0, 2, 3};

static void morph_doc(doc *g, int *pos, int *nrm, int *idx, int *t0p, int *t0n, int *t1p) {
  memset(g, 0, sizeof *g);
  *pos = floats(g, quad_pos, 4, "VEC3");
  *nrm = floats(g, quad_nrm, 4, "VEC3");
  *idx = accessor(g, view(g, quad_idx, sizeof quad_idx), U16, 6, "SCALAR", "");
  const float h = 0.70710678f;
  const float dp[12] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 1};
  const float dn[12] = {0, -h, h - 1, 0, -h, h - 1, 0, -h, h - 1, 0, -h, h - 1};
  *t0p = floats(g, dp, 4, "VEC3");
  *t0n = floats(g, dn, 4, "VEC3");
  const uint8_t si[4] = {1, 0, 0, 0};
  const float sv[3] = {2, 0, 0};
  char sparse[256];
  snprintf(sparse, sizeof sparse,
           "\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":%d,\"componentType\":5121},\"values\":{\"bufferView\":%d}}",
           view(g, si, 1), view(g, sv, sizeof sv));
  *t1p = accessor(g, -1, F32, 4, "VEC3", sparse);
}

static void test_morph_static(void) {
  doc g;
  int pos, nrm, idx, t0p, t0n, t1p;
  morph_doc(&g, &pos, &nrm, &idx, &t0p, &t0n, &t1p);
  char body[2048];
  snprintf(body, sizeof body,
           "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d},\"indices\":%d,"
           "\"targets\":[{\"POSITION\":%d,\"NORMAL\":%d},{\"POSITION\":%d}]}],\"weights\":[0.5,0]}],"
           "\"nodes\":[{\"mesh\":0},{\"mesh\":0,\"translation\":[5,0,0],\"weights\":[1,1]}],"
           "\"scenes\":[{\"nodes\":[0,1]}]",
           pos, nrm, idx, t0p, t0n, t1p);
  pb_scene s;
  CHECK_EQ_INT(load(&g, body, &s), PB_OK);
  CHECK(s.anim == NULL); /* static: posed once, nothing kept */
  CHECK(s.features & PB_FEATURE_MORPH_TARGETS);
  CHECK(!(s.features & PB_FEATURE_SKINNING));
  CHECK_EQ_INT(s.morphed_vertex_count, 8);
  CHECK_EQ_INT(s.posed_vertex_count, 0);
  CHECK_EQ_INT(s.vertex_count, 8);
  /* node 0, weights [0.5, 0] */
  VEC(s.positions[0], 0, 0, 0);
  VEC(s.positions[1], 1, 0, 0);
  VEC(s.positions[2], 1, 1, 0.5);
  VEC(s.positions[3], 0, 1, 0.5);
  double l = sqrt(0.125 + (0.5 + 0.5 * 0.70710678) * (0.5 + 0.5 * 0.70710678));
  VEC(s.normals[2], 0, -0.5 * 0.70710678 / l, (0.5 + 0.5 * 0.70710678) / l);
  /* node 1, weights [1, 1], translated by 5 */
  VEC(s.positions[4], 5, 0, 0);
  VEC(s.positions[5], 8, 0, 0);
  VEC(s.positions[6], 6, 1, 1);
  VEC(s.normals[7], 0, -0.70710678, 0.70710678);
  CHECK_NEAR(s.bounds_max[0], 8, 1e-6);
  CHECK_NEAR(s.bounds_max[2], 1, 1e-6);
  pb_scene_destroy(&s);
}

/* Morph data is bounded like vertices: target x vertex pairs at most
 * 3 x max_triangles (a target accessor without a bufferView costs the file
 * nothing, and each pair costs 12 bytes per attribute, twice). With
 * max_triangles 2 the quad (2 triangles, 4 vertices) loads with one target
 * (4 pairs of 6) and is refused with two (8). */
static void test_morph_limit(void) {
  doc g;
  int pos, nrm, idx, t0p, t0n, t1p;
  morph_doc(&g, &pos, &nrm, &idx, &t0p, &t0n, &t1p);
  pb_load_desc desc;
  memset(&desc, 0, sizeof desc);
  desc.max_triangles = 2;
  load_desc = &desc;
  char body[2048];
  const char *fmt = "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d},\"indices\":%d,"
                    "\"targets\":[{\"POSITION\":%d}%s]}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]";
  char second[32];
  snprintf(second, sizeof second, ",{\"POSITION\":%d}", t1p);
  pb_scene s;
  snprintf(body, sizeof body, fmt, pos, nrm, idx, t0p, "");
  CHECK_EQ_INT(load(&g, body, &s), PB_OK);
  CHECK_EQ_INT(s.morphed_vertex_count, 4);
  pb_scene_destroy(&s);
  snprintf(body, sizeof body, fmt, pos, nrm, idx, t0p, second);
  CHECK_EQ_INT(load(&g, body, &s), PB_ERR_LIMIT);
  CHECK(strstr(pb_error_message(), "meshes[0].primitives[0].targets: 2 morph targets x 4 vertices is over the limit of 6") != NULL);
  CHECK(strchr(pb_error_message(), '\n') == NULL);
  load_desc = NULL;
}

/* "weights" channels: node 0 LINEAR from the mesh's weights [0.5, 0] at 0 s
 * to [1, 0.5] at 1 s; node 1 CUBICSPLINE with zero tangents from [0, 0] to
 * [1, 1] over 0..2 s (at 1 s: (v0 + v1) / 2 per Hermite with u = 0.5). */
static void test_morph_animated(void) {
  doc g;
  int pos, nrm, idx, t0p, t0n, t1p;
  morph_doc(&g, &pos, &nrm, &idx, &t0p, &t0n, &t1p);
  const float t01[2] = {0, 1}, t02[2] = {0, 2};
  const float lin[4] = {0.5f, 0, 1, 0.5f};
  /* per key: in-tangents, values, out-tangents (2 targets each) */
  const float cub[12] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 0, 0};
  int in1 = floats(&g, t01, 2, "SCALAR"), in2 = floats(&g, t02, 2, "SCALAR");
  int o1 = floats(&g, lin, 4, "SCALAR");
  int o2 = floats(&g, cub, 12, "SCALAR");
  char body[4096];
  snprintf(body, sizeof body,
           "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d},\"indices\":%d,"
           "\"targets\":[{\"POSITION\":%d,\"NORMAL\":%d},{\"POSITION\":%d}]}],\"weights\":[0.5,0]}],"
           "\"nodes\":[{\"mesh\":0},{\"mesh\":0,\"translation\":[5,0,0]},{\"mesh\":0,\"translation\":[0,5,0]}],"
           "\"scenes\":[{\"nodes\":[0,1,2]}],"
           "\"animations\":[{\"samplers\":[{\"input\":%d,\"output\":%d},{\"input\":%d,\"output\":%d,\"interpolation\":\"CUBICSPLINE\"}],"
           "\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"weights\"}},"
           "{\"sampler\":1,\"target\":{\"node\":1,\"path\":\"weights\"}}]}]",
           pos, nrm, idx, t0p, t0n, t1p, in1, o1, in2, o2);
  pb_scene s;
  CHECK_EQ_INT(load(&g, body, &s), PB_OK);
  CHECK(s.anim != NULL);
  CHECK_EQ_INT(s.morphed_vertex_count, 12);
  CHECK_EQ_INT(s.posed_vertex_count, 8); /* node 2's weights never move */
  size_t pb = (size_t)s.vertex_count * sizeof *s.positions;
  float(*rest_p)[3] = malloc(pb), (*rest_n)[3] = malloc(pb);
  memcpy(rest_p, s.positions, pb);
  memcpy(rest_n, s.normals, pb);
  CHECK_EQ_INT(pb_scene_set_time(&s, 0.5), PB_OK);
  /* node 0: w = [0.75, 0.25] */
  VEC(s.positions[1], 1.5, 0, 0);
  VEC(s.positions[2], 1, 1, 0.75);
  /* node 1 at u = 0.25: h00 = 0.84375 v0 + h01 = 0.15625 v1 */
  VEC(s.positions[5], 5 + 1 + 2 * 0.15625, 0, 0);
  VEC(s.positions[6], 6, 1, 0.15625);
  /* node 2 keeps the mesh's weights */
  VEC(s.positions[10], 1, 6, 0.5);
  CHECK_EQ_INT(pb_scene_set_time(&s, 1.0), PB_OK);
  VEC(s.positions[2], 1, 1, 1);
  VEC(s.normals[2], 0, -0.70710678, 0.70710678);
  VEC(s.positions[5], 5 + 1 + 2 * 0.5, 0, 0);
  VEC(s.positions[6], 6, 1, 0.5);
  CHECK_NEAR(s.bounds_max[2], 1, 1e-6);
  /* At 0 s node 0 has the mesh's weights and node 1 [0, 0]: node 0 exactly
   * as loaded (the same arithmetic), node 1 flat. */
  CHECK_EQ_INT(pb_scene_set_time(&s, 0.0), PB_OK);
  CHECK(memcmp(rest_p, s.positions, 4 * sizeof *s.positions) == 0);
  CHECK(memcmp(rest_n, s.normals, 4 * sizeof *s.normals) == 0);
  VEC(s.positions[6], 6, 1, 0);
  free(rest_p);
  free(rest_n);
  pb_scene_destroy(&s);
}

/* A normal-mapped morphed quad: TANGENT (1,0,0,1) and a TANGENT target
 * (-1,1,0) at weight 0.5 pose the tangent (0.5,0.5,0), normalised, w kept;
 * animated to weight 1 it is +Y. The normal map is a flat 1x1 PNG. */
static void test_morph_tangent(void) {
  static const uint8_t flat_png[70] = {137,80,78,71,13,10,26,10,0,0,0,13,73,72,68,82,0,0,0,1,0,0,0,1,8,6,0,0,0,31,21,196,
                                       137,0,0,0,13,73,68,65,84,120,156,99,104,104,248,255,31,0,6,130,2,255,179,190,81,51,
                                       0,0,0,0,73,69,78,68,174,66,96,130};
  char png[256];
  snprintf(png, sizeof png, "%s/flat.png", dir);
  FILE *f = fopen(png, "wb");
  fwrite(flat_png, 1, sizeof flat_png, f);
  fclose(f);
  doc g;
  int pos, nrm, idx, t0p, t0n, t1p;
  morph_doc(&g, &pos, &nrm, &idx, &t0p, &t0n, &t1p);
  const float tan[16] = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
  const float dt[12] = {-1, 1, 0, -1, 1, 0, -1, 1, 0, -1, 1, 0};
  const float uv[8] = {0, 0, 1, 0, 1, 1, 0, 1}, t[2] = {0, 1}, w[4] = {0.5f, 0, 1, 0};
  int ta = floats(&g, tan, 4, "VEC4"), tt = floats(&g, dt, 4, "VEC3");
  int ua = accessor(&g, view(&g, uv, sizeof uv), F32, 4, "VEC2", "");
  int in = floats(&g, t, 2, "SCALAR"), out = floats(&g, w, 4, "SCALAR");
  char body[4096];
  snprintf(body, sizeof body,
           "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d,\"TANGENT\":%d,\"TEXCOORD_0\":%d},"
           "\"indices\":%d,\"material\":0,\"targets\":[{\"TANGENT\":%d},{\"POSITION\":%d}]}],\"weights\":[0.5,0]}],"
           "\"materials\":[{\"normalTexture\":{\"index\":0}}],\"textures\":[{\"source\":0}],"
           "\"images\":[{\"uri\":\"flat.png\"}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],"
           "\"animations\":[{\"samplers\":[{\"input\":%d,\"output\":%d}],"
           "\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"weights\"}}]}]",
           pos, nrm, ta, ua, idx, tt, t1p, in, out);
  pb_scene s;
  CHECK_EQ_INT(load(&g, body, &s), PB_OK);
  CHECK(s.tangents != NULL);
  if (s.tangents) {
    const double h = 0.70710678;
    VEC(s.tangents[0], h, h, 0);
    CHECK_NEAR(s.tangents[0][3], 1, 0);
    CHECK_EQ_INT(pb_scene_set_time(&s, 1.0), PB_OK);
    VEC(s.tangents[2], 0, 1, 0);
    CHECK_EQ_INT(pb_scene_set_time(&s, 0.0), PB_OK);
    VEC(s.tangents[3], h, h, 0);
  }
  pb_scene_destroy(&s);
  unlink(png);
}

/* ---- skins ------------------------------------------------------------------
 * A strip along x: vertices (x, y, 0) for x = 0, 1, 2 and y = 0, 1 (index
 * 2x + y), normals +Z. Joint 0 (node 1) at the origin, joint 1 (node 2, its
 * child) at (1,0,0); inverse bind matrices identity and T(-1,0,0). x = 0 is
 * bound to joint 0, x = 1 half and half, x = 2 to joint 1 (over two sets:
 * 0.5 in WEIGHTS_0 and 0.5 in WEIGHTS_1). Rotating joint 1 about Y by a turns
 * the x = 2 vertices about the axis x = 1: (2,y,0) -> (1 + cos a, y, -sin a),
 * their normal +Z -> (sin a, 0, cos a); the x = 1 vertices lie on the axis.
 * The skinned node (node 0) is translated by (100,0,0), which glTF ignores. */

static const char *strip_body(doc *g, char *body, size_t n, const char *j1_rotation, const char *animations,
                              const float *weights0) {
  memset(g, 0, sizeof *g);
  const float pos[18] = {0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0, 2, 1, 0};
  float nz[18];
  for (int i = 0; i < 6; ++i) nz[3 * i] = 0, nz[3 * i + 1] = 0, nz[3 * i + 2] = 1;
  const uint16_t idx[12] = {0, 2, 3, 0, 3, 1, 2, 4, 5, 2, 5, 3};
  const uint8_t j0[24] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  const uint8_t j1[24] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  const float w1[24] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0, 0, 0};
  const float ibm[32] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0, 0, 1};
  int pa = floats(g, pos, 6, "VEC3"), na = floats(g, nz, 6, "VEC3");
  int ia = accessor(g, view(g, idx, sizeof idx), U16, 12, "SCALAR", "");
  int ja0 = accessor(g, view(g, j0, sizeof j0), U8, 6, "VEC4", "");
  int ja1 = accessor(g, view(g, j1, sizeof j1), U8, 6, "VEC4", "");
  int wa0 = floats(g, weights0, 6, "VEC4"), wa1 = floats(g, w1, 6, "VEC4");
  int ba = floats(g, ibm, 2, "MAT4");
  snprintf(body, n,
           "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d,\"JOINTS_0\":%d,\"WEIGHTS_0\":%d,"
           "\"JOINTS_1\":%d,\"WEIGHTS_1\":%d},\"indices\":%d}]}],"
           "\"skins\":[{\"joints\":[1,2],\"inverseBindMatrices\":%d,\"skeleton\":1}],"
           "\"nodes\":[{\"mesh\":0,\"skin\":0,\"translation\":[100,0,0]},{\"children\":[2]},"
           "{\"translation\":[1,0,0]%s}],"
           "\"scenes\":[{\"nodes\":[0,1]}]%s",
           pa, na, ja0, wa0, ja1, wa1, ia, ba, j1_rotation, animations);
  return body;
}

static const float strip_weights[24] = {1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.5f, 0.5f, 0, 0,
                                        0.5f, 0, 0, 0, 0.5f, 0, 0, 0};

static void check_strip(const pb_scene *s, double a, int line) {
  double c = cos(a), sn = sin(a);
  const float *p = s->positions[0];
  check_vec(p, 0, 0, 0, 1e-5, line);
  check_vec(s->positions[1], 0, 1, 0, 1e-5, line);
  check_vec(s->positions[2], 1, 0, 0, 1e-5, line);
  check_vec(s->positions[3], 1, 1, 0, 1e-5, line);
  check_vec(s->positions[4], 1 + c, 0, -sn, 1e-5, line);
  check_vec(s->positions[5], 1 + c, 1, -sn, 1e-5, line);
  check_vec(s->normals[0], 0, 0, 1, 1e-5, line);
  check_vec(s->normals[5], sn, 0, c, 1e-5, line);
  /* half and half: the skin matrix's 3x3 is (I + R_y(a)) / 2, whose
   * inverse transpose turns +Z by a / 2 */
  check_vec(s->normals[3], sin(a / 2), 0, cos(a / 2), 1e-5, line);
}

static void test_skin_static(void) {
  doc g;
  char body[4096];
  /* joint 1 rotated 90 degrees about Y in the file, no animation */
  strip_body(&g, body, sizeof body, ",\"rotation\":[0,0.70710678,0,0.70710678]", "", strip_weights);
  pb_scene s;
  CHECK_EQ_INT(load(&g, body, &s), PB_OK);
  CHECK(s.anim == NULL);
  CHECK(s.features & PB_FEATURE_SKINNING);
  CHECK_EQ_INT(s.skinned_vertex_count, 6);
  CHECK_EQ_INT(s.posed_vertex_count, 0);
  check_strip(&s, M_PI / 2, __LINE__);
  CHECK_NEAR(s.bounds_min[2], -1, 1e-5);
  for (uint32_t i = 0; i < s.warning_count; ++i) CHECK(strstr(s.warnings[i], "skin") == NULL);
  pb_scene_destroy(&s);
}

static void test_skin_animated(void) {
  doc g;
  char body[4096];
  const float h = 0.70710678f, t[2] = {0, 1}, q[8] = {0, 0, 0, 1, 0, h, 0, h};
  /* strip_body makes accessors 0..7; the keys are 8 and 9 */
  const char *anim = ",\"animations\":[{\"samplers\":[{\"input\":8,\"output\":9}],"
                     "\"channels\":[{\"sampler\":0,\"target\":{\"node\":2,\"path\":\"rotation\"}}]}]";
  strip_body(&g, body, sizeof body, "", anim, strip_weights);
  CHECK_EQ_INT(floats(&g, t, 2, "SCALAR"), 8);
  CHECK_EQ_INT(floats(&g, q, 2, "VEC4"), 9);
  pb_scene s;
  CHECK_EQ_INT(load(&g, body, &s), PB_OK);
  CHECK(s.anim != NULL);
  CHECK_EQ_INT(s.posed_vertex_count, 6);
  check_strip(&s, 0, __LINE__);
  size_t pb = (size_t)s.vertex_count * sizeof *s.positions;
  float(*rest)[3] = malloc(pb);
  memcpy(rest, s.positions, pb);
  uint32_t tri[4][3];
  memcpy(tri, s.triangles, sizeof tri);
  CHECK_EQ_INT(pb_scene_set_time(&s, 1.0), PB_OK);
  check_strip(&s, M_PI / 2, __LINE__);
  CHECK_EQ_INT(pb_scene_set_time(&s, 0.5), PB_OK);
  check_strip(&s, M_PI / 4, __LINE__); /* slerp: half the angle */
  CHECK(memcmp(tri, s.triangles, sizeof tri) == 0); /* topology never changes */
  CHECK_EQ_INT(pb_scene_set_time(&s, 0.0), PB_OK);
  CHECK(memcmp(rest, s.positions, pb) == 0);
  free(rest);
  pb_scene_destroy(&s);
}

/* Repairs: vertex 0 without any weight follows its mesh node (at x + 100),
 * vertex 1's weights sum to 0.5 and are rescaled to 1. */
static void test_skin_repairs(void) {
  doc g;
  char body[4096];
  float w[24];
  memcpy(w, strip_weights, sizeof w);
  w[0] = 0;   /* vertex 0: nothing */
  w[4] = 0.5; /* vertex 1: half a weight on joint 0 */
  strip_body(&g, body, sizeof body, ",\"rotation\":[0,0.70710678,0,0.70710678]", "", w);
  pb_scene s;
  CHECK_EQ_INT(load(&g, body, &s), PB_OK);
  CHECK(has_warning(&s, "meshes[0].primitives[0]: skin weights of 1 of 6 vertices do not sum to 1 (worst 0.5); rescaled to 1"));
  CHECK(has_warning(&s, "meshes[0].primitives[0]: 1 of 6 vertices have no skin weight; they follow their mesh node"));
  VEC(s.positions[0], 100, 0, 0);
  VEC(s.positions[1], 0, 1, 0);
  VEC(s.positions[4], 1, 0, -1);
  pb_scene_destroy(&s);
}

/* Errors with their JSON paths. */
static void test_skin_errors(void) {
  doc g;
  char body[4096];
  strip_body(&g, body, sizeof body, "", "", strip_weights);
  char *p = strstr(body, "\"joints\":[1,2]");
  memcpy(p, "\"joints\":[1,9]", 14);
  pb_scene s;
  CHECK_EQ_INT(load(&g, body, &s), PB_ERR_SCENE_INVALID);
  CHECK(strstr(pb_error_message(), "skins[0].joints[1]: node 9 does not exist") != NULL);
  float w[24];
  memcpy(w, strip_weights, sizeof w);
  w[1] = -0.25f;
  strip_body(&g, body, sizeof body, "", "", w);
  CHECK_EQ_INT(load(&g, body, &s), PB_ERR_SCENE_INVALID);
  CHECK(strstr(pb_error_message(), "meshes[0].primitives[0].attributes.WEIGHTS_0: accessor 5 element 0 has weight -0.25") != NULL);
}

int main(void) {
  if (!mkdtemp(dir)) return 1;
  test_morph_static();
  test_morph_animated();
  test_morph_tangent();
  test_morph_limit();
  test_skin_static();
  test_skin_animated();
  test_skin_repairs();
  test_skin_errors();
  rmdir(dir);
  return pbt_done();
}
