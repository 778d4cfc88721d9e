/* Normal-map tangent frames (src/scene/tangents.c) and the loader's TANGENT
 * attribute (src/scene/load.c), GPU-free: generated tangents and handedness
 * on a uv-mapped quad (and its mirrored mapping), a degenerate mapping (any
 * orthonormal tangent, no NaN), TANGENT read and moved to world space (a
 * rotation; a mirror flips w), scenes without normal maps get no tangents,
 * and bad TANGENT accessors fail with PB_ERR_SCENE_INVALID and one line.
 * Plus eq. 20's factor (src/render/estimate/shading_correction.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/srgb.h"
#include "image/image.h"
#include "pbtest.h"
#include "gltf_test.h"
#include "render/estimate/shading_correction.h"
#include "scene/scene.h"
#include "scene/tangents.h"

static char dir[] = "/tmp/pbtest_tangents_XXXXXX";


/* Unit quad in the XY plane, normal +Z, u = x, v = 1 - y (glTF: v runs down
 * the image), so dP/du = +X, -dP/dv = +Y: T = +X, w = +1. */
static const float quad_pos[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
static const float quad_nrm[4][3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
static const float quad_uv[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
static const uint32_t quad_tri[2][3] = {{0, 1, 2}, {0, 2, 3}};

static void test_generate(void) {
  float t[4][4];
  CHECK_EQ_INT(pb_tangents_generate(quad_pos, quad_nrm, quad_uv, 4, quad_tri, 2, NULL, t), PB_OK);
  for (int v = 0; v < 4; ++v) {
    CHECK_NEAR(t[v][0], 1, 1e-6);
    CHECK_NEAR(t[v][1], 0, 1e-6);
    CHECK_NEAR(t[v][2], 0, 1e-6);
    CHECK_NEAR(t[v][3], 1, 0);
  }
  /* Mirrored in u (u = 1 - x): T = -X and, with the image's up still +Y,
   * cross(N, T) = -Y is the wrong way: w = -1. */
  float uvm[4][2];
  for (int v = 0; v < 4; ++v) uvm[v][0] = 1 - quad_uv[v][0], uvm[v][1] = quad_uv[v][1];
  CHECK_EQ_INT(pb_tangents_generate(quad_pos, quad_nrm, uvm, 4, quad_tri, 2, NULL, t), PB_OK);
  for (int v = 0; v < 4; ++v) {
    CHECK_NEAR(t[v][0], -1, 1e-6);
    CHECK_NEAR(t[v][3], -1, 0);
  }
  /* Rotated mapping: u along +Y, v along +X (so image up = -X):
   * T = +Y, cross(Z, Y) = -X = image up: w = +1. */
  float uvr[4][2];
  for (int v = 0; v < 4; ++v) uvr[v][0] = quad_pos[v][1], uvr[v][1] = quad_pos[v][0];
  CHECK_EQ_INT(pb_tangents_generate(quad_pos, quad_nrm, uvr, 4, quad_tri, 2, NULL, t), PB_OK);
  CHECK_NEAR(t[0][1], 1, 1e-6);
  CHECK_NEAR(t[0][3], 1, 0);
  /* Tilted vertex normals: T is re-orthogonalised against each. */
  float nt[4][3];
  for (int v = 0; v < 4; ++v) nt[v][0] = 0.6f, nt[v][1] = 0, nt[v][2] = 0.8f;
  CHECK_EQ_INT(pb_tangents_generate(quad_pos, nt, quad_uv, 4, quad_tri, 2, NULL, t), PB_OK);
  CHECK_NEAR(t[1][0] * 0.6f + t[1][2] * 0.8f, 0, 1e-6);
  CHECK_NEAR(t[1][0], 0.8, 1e-6);
  CHECK_NEAR(t[1][2], -0.6, 1e-6);
  /* Degenerate uvs (all equal) and no uvs: any unit tangent orthogonal to
   * N, w = +1, nothing NaN. */
  float uvz[4][2] = {{0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}};
  for (int k = 0; k < 2; ++k) {
    CHECK_EQ_INT(pb_tangents_generate(quad_pos, quad_nrm, k ? NULL : (const float(*)[2])uvz, 4, quad_tri, 2, NULL, t), PB_OK);
    for (int v = 0; v < 4; ++v) {
      CHECK(isfinite(t[v][0]) && isfinite(t[v][1]) && isfinite(t[v][2]) && isfinite(t[v][3]));
      CHECK_NEAR(t[v][0] * t[v][0] + t[v][1] * t[v][1] + t[v][2] * t[v][2], 1, 1e-6);
      CHECK_NEAR(t[v][2], 0, 1e-6);
      CHECK_NEAR(t[v][3], 1, 0);
    }
  }
  /* Given tangents are kept (re-orthogonalised, w to a sign). */
  uint8_t given[4] = {1, 0, 0, 0};
  t[0][0] = 0, t[0][1] = 2, t[0][2] = 0.1f, t[0][3] = -0.5f;
  CHECK_EQ_INT(pb_tangents_generate(quad_pos, quad_nrm, quad_uv, 4, quad_tri, 2, given, t), PB_OK);
  CHECK_NEAR(t[0][1], 1, 1e-6);
  CHECK_NEAR(t[0][2], 0, 1e-6);
  CHECK_NEAR(t[0][3], -1, 0);
  CHECK_NEAR(t[1][0], 1, 1e-6);
}

/* The quad as a glTF file with a normal-mapped material (a 2 x 2 PNG next to
 * it). tangent: NULL for none, else "VEC4" or another type to break it;
 * tan_count: the TANGENT accessor's count. node: the node JSON. normal_map:
 * 0 leaves the material without normalTexture. */
static pb_result load_quad(const char *tangent, int tan_count, const char *node, int normal_map, pb_scene *s) {
  uint8_t buf[48 + 48 + 32 + 64 + 12];
  memcpy(buf, quad_pos, 48);
  memcpy(buf + 48, quad_nrm, 48);
  memcpy(buf + 96, quad_uv, 32);
  float tg[4][4];
  for (int v = 0; v < 4; ++v) tg[v][0] = 0, tg[v][1] = 1, tg[v][2] = 0, tg[v][3] = -1; /* T = +Y, w = -1 */
  memcpy(buf + 128, tg, 64);
  uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
  memcpy(buf + 192, idx, 12);
  char *data = pbt_b64(buf, sizeof buf);
  char png[256], path[256];
  snprintf(png, sizeof png, "%s/n.png", dir);
  /* Flat normal map (128, 128, 255): bytes written through the sRGB encode. */
  float px[4 * 3];
  for (int i = 0; i < 4; ++i)
    px[3 * i] = px[3 * i + 1] = pb_srgb_to_linear(128.0f / 255.0f), px[3 * i + 2] = 1.0f;
  pb_result r = pb_png_write_srgb(png, 2, 2, 3, px, 0.0f);
  CHECK_EQ_INT(r, PB_OK);
  snprintf(path, sizeof path, "%s/q.gltf", dir);
  FILE *f = fopen(path, "w");
  char tattr[64] = "";
  if (tangent) snprintf(tattr, sizeof tattr, ",\"TANGENT\":3");
  fprintf(f,
          "{\"asset\":{\"version\":\"2.0\"},"
          "\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,%s\",\"byteLength\":%zu}],"
          "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":48},"
          "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":32},{\"buffer\":0,\"byteOffset\":128,\"byteLength\":64},"
          "{\"buffer\":0,\"byteOffset\":192,\"byteLength\":12}],"
          "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
          "{\"bufferView\":1,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
          "{\"bufferView\":2,\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"
          "{\"bufferView\":3,\"componentType\":5126,\"count\":%d,\"type\":\"%s\"},"
          "{\"bufferView\":4,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
          "\"images\":[{\"uri\":\"n.png\"}],\"textures\":[{\"source\":0}],"
          "\"materials\":[{\"name\":\"m\"%s}],"
          "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1,\"TEXCOORD_0\":2%s},"
          "\"indices\":4,\"material\":0}]}],"
          "\"nodes\":[%s],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}",
          data, sizeof buf, tan_count, tangent ? tangent : "VEC4",
          normal_map ? ",\"normalTexture\":{\"index\":0,\"scale\":0.5}" : "", tattr, node);
  fclose(f);
  free(data);
  pb_error_clear();
  r = pb_scene_load(path, NULL, s);
  unlink(path);
  unlink(png);
  return r;
}

static void test_loader(void) {
  pb_scene s;
  /* No TANGENT: generated, T = +X, w = +1. */
  CHECK_EQ_INT(load_quad(NULL, 4, "{\"mesh\":0}", 1, &s), PB_OK);
  CHECK(s.features & PB_FEATURE_NORMAL_MAPS);
  CHECK(s.tangents != NULL);
  if (s.tangents) {
    CHECK_NEAR(s.tangents[0][0], 1, 1e-6);
    CHECK_NEAR(s.tangents[0][3], 1, 0);
  }
  CHECK_NEAR(s.materials[0].normal_scale, 0.5, 1e-6);
  CHECK(s.materials[0].normal_tex >= 0 && !s.textures[s.materials[0].normal_tex].srgb);
  pb_scene_destroy(&s);
  /* TANGENT read: (0, 1, 0, -1) kept. */
  CHECK_EQ_INT(load_quad("VEC4", 4, "{\"mesh\":0}", 1, &s), PB_OK);
  if (s.tangents) {
    CHECK_NEAR(s.tangents[2][1], 1, 1e-6);
    CHECK_NEAR(s.tangents[2][3], -1, 0);
  }
  pb_scene_destroy(&s);
  /* World space: a 90-degree rotation about Z takes +Y to -X; a mirror in X
   * (scale -1, 1, 1) keeps +Y and flips w. */
  CHECK_EQ_INT(load_quad("VEC4", 4, "{\"mesh\":0,\"rotation\":[0,0,0.70710678,0.70710678]}", 1, &s), PB_OK);
  if (s.tangents) {
    CHECK_NEAR(s.tangents[0][0], -1, 1e-6);
    CHECK_NEAR(s.tangents[0][1], 0, 1e-6);
    CHECK_NEAR(s.tangents[0][3], -1, 0);
  }
  pb_scene_destroy(&s);
  CHECK_EQ_INT(load_quad("VEC4", 4, "{\"mesh\":0,\"scale\":[-1,1,1]}", 1, &s), PB_OK);
  if (s.tangents) {
    CHECK_NEAR(s.tangents[0][1], 1, 1e-6);
    CHECK_NEAR(s.tangents[0][3], 1, 0);
  }
  pb_scene_destroy(&s);
  /* Without a normal map: no tangents at all, TANGENT or not. */
  CHECK_EQ_INT(load_quad("VEC4", 4, "{\"mesh\":0}", 0, &s), PB_OK);
  CHECK(s.tangents == NULL);
  CHECK(!(s.features & PB_FEATURE_NORMAL_MAPS));
  pb_scene_destroy(&s);
  /* Bad TANGENT accessors: wrong type, wrong count. */
  CHECK_EQ_INT(load_quad("VEC3", 4, "{\"mesh\":0}", 1, &s), PB_ERR_SCENE_INVALID);
  const char *m = pb_error_message();
  printf("VEC3 TANGENT: %s\n", m);
  CHECK(strstr(m, "accessors[3]: has 3 components, meshes[0].primitives[0].attributes.TANGENT needs 4") != NULL);
  CHECK(strchr(m, '\n') == NULL);
  CHECK_EQ_INT(load_quad("VEC4", 3, "{\"mesh\":0}", 1, &s), PB_ERR_SCENE_INVALID);
  m = pb_error_message();
  printf("short TANGENT: %s\n", m);
  CHECK(strstr(m, "TANGENT: accessor 3 has 3 elements, POSITION has 4") != NULL);
  pb_error_clear();
}

static void test_eq20_factor(void) {
  float ng[3] = {0, 0, 1};
  float s = PB_SHADING_CORRECTION_S_MAX;
  /* Light at 45 degrees; n_s tilted 30 degrees towards it: cos 15 / cos 45. */
  float wi[3] = {sinf((float)M_PI / 4), 0, cosf((float)M_PI / 4)};
  float ns[3] = {sinf((float)M_PI / 6), 0, cosf((float)M_PI / 6)};
  CHECK_NEAR(pb_shading_correction_factor(wi, ns, ng, s), cos(M_PI / 12) / (cos(M_PI / 4) + 1e-3), 1e-5);
  /* n_s = n_g: 1 up to eps. */
  CHECK_NEAR(pb_shading_correction_factor(wi, ng, ng, s), 1, 2e-3);
  /* Grazing light: clamped at s_max. */
  float gr[3] = {0.99999f, 0, 0.0044f};
  CHECK_NEAR(pb_shading_correction_factor(gr, ns, ng, s), s, 0);
  /* Light below n_s: 0. No photon: 1. */
  float below[3] = {-0.9f, 0, 0.1f};
  CHECK_NEAR(pb_shading_correction_factor(below, ns, ng, s), 0, 0);
  float zero[3] = {0, 0, 0};
  CHECK_NEAR(pb_shading_correction_factor(zero, ns, ng, s), 1, 0);
}

int main(void) {
  if (!mkdtemp(dir)) return 1;
  test_generate();
  test_loader();
  test_eq20_factor();
  rmdir(dir);
  return pbt_done();
}
