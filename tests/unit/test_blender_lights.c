/* PHOTONBRIDGE_blender lights and world in the loader (src/scene/
 * blender_lights.c) and the Radiance HDR decoder (src/image/hdr.c):
 *  - Blender's units converted with Cycles 3.4's conventions: I = P / 4 pi,
 *    area radiance P / (4 A) for each shape, the sun's W/m^2, colours, the
 *    spot's half-angle and Cycles falloff, radius, angle, spread, shadow and
 *    MIS flags; the area light's axes from its node; the extension's light
 *    replaces the node's KHR light (one light, not two) and stands alone on
 *    a node without one; a file without the extension keeps its KHR lights,
 *    no world, coverage alpha;
 *  - the world: colour x strength, an EXR map (written here) x both
 *    strengths, its Mapping rotation against an independently composed
 *    matrix (glTF -> Blender axes, then Rz Ry Rx), hidden from the camera,
 *    Film > Transparent;
 *  - the HDR decoder on flat, old-style and new-style run-length scanlines
 *    and bottom-up files, exact values (m + 1/2) 2^(e - 136), and malformed
 *    files (runs past the line, zero counts, a wrong line width, truncation,
 *    an XYZE header) as PB_ERR_IMAGE, a huge header as PB_ERR_LIMIT before
 *    any allocation. GPU-free. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "gltf_test.h"
#include "image/hdr.h"
#include "image/image.h"
#include "pbtest.h"
#include "scene/scene.h"
#include "scene/world.h"

static char dir[] = "/tmp/pbtest_blender_XXXXXX";

/* A 2 x 2 m quad (y = 0, facing +y) and `nodes`, `extra` of the file. */
static pb_result load(const char *nodes, int n_nodes, const char *extra, pb_scene *s) {
  float v[12] = {-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1};
  uint16_t idx[6] = {0, 2, 1, 0, 3, 2};
  uint8_t blob[60];
  memcpy(blob, v, 48);
  memcpy(blob + 48, idx, 12);
  char *data = pbt_b64(blob, sizeof blob);
  char path[256], roots[64] = "0,1";
  for (int i = 0; i < n_nodes; ++i) snprintf(roots + strlen(roots), sizeof roots - strlen(roots), ",%d", i + 2);
  snprintf(path, sizeof path, "%s/t.gltf", dir);
  FILE *f = fopen(path, "w");
  fprintf(f,
          "{\"asset\":{\"version\":\"2.0\"},"
          "\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,%s\",\"byteLength\":60}],"
          "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":12}],"
          "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
          "\"min\":[-1,0,-1],\"max\":[1,0,1]},{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
          "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
          "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,\"znear\":0.1}}],"
          "\"nodes\":[{\"mesh\":0},{\"camera\":0,\"translation\":[0,1,5]}%s%s],"
          "\"scenes\":[{\"nodes\":[%s]}],\"scene\":0%s%s}",
          data, nodes[0] ? "," : "", nodes, roots, extra[0] ? "," : "", extra);
  fclose(f);
  free(data);
  pb_error_clear();
  pb_load_desc d = {0};
  pb_result r = pb_scene_load(path, &d, s);
  unlink(path);
  return r;
}

static const pb_light *find(const pb_scene *s, const char *name) {
  for (uint32_t i = 0; i < s->light_count; ++i)
    if (strcmp(s->lights[i].name, name) == 0) return &s->lights[i];
  return NULL;
}

static void test_lights(void) {
  /* Node rotations: -90 degrees about X turns -Z into -Y (down). */
  const char *nodes =
      "{\"name\":\"Bulb\",\"translation\":[0,2,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0},"
      "\"PHOTONBRIDGE_blender\":{\"light\":{\"type\":\"POINT\",\"power\":100,\"radius\":0.2,\"color\":[1,0.5,0.25],"
      "\"castShadow\":false}}}},"
      "{\"name\":\"Spot\",\"rotation\":[-0.70710678,0,0,0.70710678],\"extensions\":{\"PHOTONBRIDGE_blender\":"
      "{\"light\":{\"type\":\"SPOT\",\"power\":400,\"spotSize\":1.0,\"spotBlend\":0.2,\"useMIS\":false}}}},"
      "{\"name\":\"Sun\",\"rotation\":[-0.70710678,0,0,0.70710678],\"extensions\":{\"PHOTONBRIDGE_blender\":"
      "{\"light\":{\"type\":\"SUN\",\"strength\":3,\"angle\":0.1}}}},"
      "{\"name\":\"Disc\",\"translation\":[0,1.5,0],\"rotation\":[-0.5,-0.5,-0.5,0.5],\"extensions\":"
      "{\"PHOTONBRIDGE_blender\":{\"light\":{\"type\":\"AREA\",\"power\":50,\"shape\":\"DISK\",\"size\":0.5,"
      "\"sizeY\":9,\"spread\":1.0}}}},"
      "{\"name\":\"Panel\",\"extensions\":{\"PHOTONBRIDGE_blender\":{\"light\":{\"type\":\"AREA\",\"power\":80,"
      "\"shape\":\"ELLIPSE\",\"size\":2,\"sizeY\":0.5}}}}";
  const char *extra =
      "\"extensionsUsed\":[\"KHR_lights_punctual\",\"PHOTONBRIDGE_blender\"],"
      "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"point\",\"intensity\":999}]}}";
  pb_scene s;
  CHECK_EQ_INT(load(nodes, 5, extra, &s), PB_OK);
  if (s.light_count != 5) {
    CHECK_EQ_INT(s.light_count, 5); /* the KHR light of Bulb is not counted */
    pb_scene_destroy(&s);
    return;
  }
  const pb_light *b = find(&s, "Bulb"), *sp = find(&s, "Spot"), *sun = find(&s, "Sun"), *disc = find(&s, "Disc"),
                 *pan = find(&s, "Panel");
  CHECK(b && sp && sun && disc && pan);
  if (!(b && sp && sun && disc && pan)) {
    pb_scene_destroy(&s);
    return;
  }
  CHECK_EQ_INT(b->type, PB_LIGHT_POINT);
  CHECK_NEAR(b->intensity, 100 / (4 * M_PI), 1e-5);
  CHECK_NEAR(b->file_intensity, 100, 1e-5);
  CHECK_NEAR(b->radius, 0.2, 1e-7);
  CHECK_NEAR(b->color[1], 0.5, 1e-7);
  CHECK_EQ_INT(b->no_shadow, 1);
  CHECK_EQ_INT(b->from_blender, 1);
  CHECK_NEAR(b->position[1], 2, 1e-6);
  CHECK_EQ_INT(pb_light_is_delta(b), 0);
  CHECK_EQ_INT(sp->type, PB_LIGHT_SPOT);
  CHECK_EQ_INT(sp->spot_model, PB_SPOT_CYCLES);
  CHECK_NEAR(sp->outer_cone, 0.5, 1e-7);
  CHECK_NEAR(sp->spot_blend, 0.2, 1e-7);
  CHECK_NEAR(sp->intensity, 400 / (4 * M_PI), 1e-4);
  CHECK_NEAR(sp->radius, 0.1, 1e-7); /* the contract's default */
  CHECK_NEAR(sp->direction[1], -1, 1e-6);
  CHECK_EQ_INT(sp->no_mis, 1);
  CHECK_EQ_INT(sun->type, PB_LIGHT_DIRECTIONAL);
  CHECK_NEAR(sun->intensity, 3, 1e-7);
  CHECK_NEAR(sun->angle, 0.1, 1e-7);
  CHECK_NEAR(sun->direction[1], -1, 1e-6);
  /* DISK: sizeY is ignored, area pi 0.5^2 / 4, radiance P / (4 A). */
  CHECK_EQ_INT(disc->type, PB_LIGHT_AREA);
  CHECK_EQ_INT(disc->shape, PB_AREA_ELLIPSE);
  CHECK_NEAR(disc->size[1], 0.5, 1e-7);
  CHECK_NEAR(pb_light_area(disc), M_PI * 0.25 / 4, 1e-6);
  CHECK_NEAR(disc->intensity, 50 / (4 * M_PI * 0.25 / 4), 1e-3);
  CHECK_NEAR(disc->spread, 1.0, 1e-7);
  /* The quaternion (-0.5, -0.5, -0.5, 0.5), 120 degrees about -(1, 1, 1),
   * turns X to Z, Y to X and Z to Y: the disc faces down (-Z to -Y) with
   * axis_u along +Z and axis_v along +X. */
  CHECK_NEAR(disc->direction[1], -1, 1e-6);
  CHECK_NEAR(disc->axis_u[2], 1, 1e-6);
  CHECK_NEAR(fabs(disc->axis_v[0]), 1, 1e-6);
  CHECK_NEAR(pan->intensity, 80 / (4 * M_PI * 2 * 0.5 / 4), 1e-3);
  CHECK_NEAR(pan->spread, M_PI, 1e-6);
  CHECK(s.features & PB_FEATURE_SOFT_LIGHTS);
  CHECK_EQ_INT(s.world.present, 0);
  /* Without render.filmTransparent the film is opaque... */
  pb_scene_destroy(&s);

  /* ... but only with the root extension; none here: coverage alpha. */
  CHECK_EQ_INT(s.film_opaque, 0);
  /* A file without the extension: KHR as before. */
  const char *khr = "{\"name\":\"Bulb\",\"translation\":[0,2,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}}";
  const char *khr_extra = "\"extensionsUsed\":[\"KHR_lights_punctual\"],"
                          "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"point\",\"intensity\":683}]}}";
  CHECK_EQ_INT(load(khr, 1, khr_extra, &s), PB_OK);
  CHECK_EQ_INT(s.light_count, 1);
  if (s.light_count == 1) {
    CHECK_NEAR(s.lights[0].intensity, 1.0, 1e-6);
    CHECK_EQ_INT(s.lights[0].from_blender, 0);
    CHECK_EQ_INT(pb_light_is_delta(&s.lights[0]), 1);
  }
  CHECK_EQ_INT(s.film_opaque, 0);
  CHECK_EQ_INT(s.world.present, 0);
  CHECK(!(s.features & (PB_FEATURE_SOFT_LIGHTS | PB_FEATURE_WORLD)));
  pb_scene_destroy(&s);
}

static void test_world(void) {
  /* A 4 x 2 EXR map: texel (x, y) = (x + 1, y + 1, 0.5). */
  float px[4 * 2 * 3];
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      px[3 * (y * 4 + x)] = (float)(x + 1);
      px[3 * (y * 4 + x) + 1] = (float)(y + 1);
      px[3 * (y * 4 + x) + 2] = 0.5f;
    }
  char exr[256];
  snprintf(exr, sizeof exr, "%s/sky.exr", dir);
  pb_image_layer layer = {"", 3, px, NULL};
  pb_exr_desc ed = {.width = 4, .height = 2, .layers = &layer, .layer_count = 1};
  CHECK_EQ_INT(pb_exr_write(exr, &ed), PB_OK);
  const char *extra =
      "\"extensionsUsed\":[\"PHOTONBRIDGE_blender\"],"
      "\"extensions\":{\"PHOTONBRIDGE_blender\":{\"version\":1,\"render\":{\"filmTransparent\":true},"
      "\"world\":{\"color\":[9,9,9],\"strength\":2,\"visibleToCamera\":false,"
      "\"environment\":{\"uri\":\"sky.exr\",\"rotation\":[0.4,-0.3,1.2],\"strength\":1.5}}}}";
  pb_scene s;
  CHECK_EQ_INT(load("", 0, extra, &s), PB_OK);
  const pb_world *w = &s.world;
  CHECK_EQ_INT(w->present, 1);
  CHECK_EQ_INT(s.film_opaque, 0);
  CHECK_EQ_INT(w->hidden_from_camera, 1);
  CHECK(w->env != NULL);
  if (w->env) {
    CHECK_EQ_INT(w->env_width, 4);
    CHECK_EQ_INT(w->env_height, 2);
    CHECK_NEAR(w->env_scale, 3.0, 1e-6);
    CHECK_NEAR(w->env[3 * (1 * 4 + 2)], 3.0, 0);     /* x = 2, y = 1 */
    CHECK_NEAR(w->env[3 * (1 * 4 + 2) + 1], 2.0, 0);
    /* env_to_map = R(e) C, composed here axis by axis. */
    double e[3] = {0.4, -0.3, 1.2};
    for (int k = 0; k < 3; ++k) {
      double g[3] = {k == 0, k == 1, k == 2}, b[3] = {g[0], -g[2], g[1]};
      double cx = cos(e[0]), sx = sin(e[0]), cy = cos(e[1]), sy = sin(e[1]), cz = cos(e[2]), sz = sin(e[2]);
      double x1[3] = {b[0], cx * b[1] - sx * b[2], sx * b[1] + cx * b[2]};
      double y1[3] = {cy * x1[0] + sy * x1[2], x1[1], -sy * x1[0] + cy * x1[2]};
      double m[3] = {cz * y1[0] - sz * y1[1], sz * y1[0] + cz * y1[1], y1[2]};
      for (int r = 0; r < 3; ++r) CHECK_NEAR(w->env_to_map[3 * r + k], m[r], 1e-6);
    }
    /* The integral: every texel's mean over its cell times the cell's
     * solid angle, summed; here the map's linear ramp keeps it simple to
     * bound: between the smallest and largest texel x 4 pi x scale. */
    CHECK(w->integral[0] > 3.0 * 4 * M_PI && w->integral[0] < 3.0 * 4 * M_PI * 4);
  }
  CHECK(s.features & PB_FEATURE_WORLD);
  pb_scene_destroy(&s);
  unlink(exr);

  /* A constant world, default strength; a black one is no world. */
  CHECK_EQ_INT(load("", 0, "\"extensions\":{\"PHOTONBRIDGE_blender\":{\"version\":1,\"world\":{\"color\":[0.2,0.4,0.6]}}}", &s),
               PB_OK);
  CHECK_EQ_INT(s.world.present, 1);
  CHECK_NEAR(s.world.color[2], 0.6, 1e-7);
  CHECK_NEAR(s.world.integral[1], 0.4 * 4 * M_PI, 1e-5);
  CHECK_EQ_INT(s.film_opaque, 1);
  float d[3] = {0.3f, 0.9f, 0.1f}, L[3];
  pb_world_radiance(&s.world, d, L);
  CHECK_NEAR(L[0], 0.2, 1e-7);
  pb_scene_destroy(&s);
  CHECK_EQ_INT(load("", 0, "\"extensions\":{\"PHOTONBRIDGE_blender\":{\"version\":1,\"world\":{\"color\":[0,0,0]}}}", &s), PB_OK);
  CHECK_EQ_INT(s.world.present, 0);
  pb_scene_destroy(&s);
}

/* ---- the HDR decoder ----------------------------------------------------- */

static size_t put(uint8_t *o, const char *s) {
  size_t n = strlen(s);
  memcpy(o, s, n);
  return n;
}

static float rgbe(uint8_t m, uint8_t e) { return e ? (m + 0.5f) * ldexpf(1.0f, (int)e - 136) : 0.0f; }

static void test_hdr(void) {
  uint8_t f[4096];
  size_t n;
  float *px;
  uint32_t w, h;
  char why[160];
  /* Flat, 2 x 2, with an old-style run (1 1 1 1: the last pixel once more)
   * in row 1. */
  n = put(f, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1\n\n-Y 2 +X 2\n");
  uint8_t flat[] = {10, 20, 30, 130, 255, 0, 1, 120, 7, 8, 9, 129, 1, 1, 1, 1};
  memcpy(f + n, flat, sizeof flat);
  n += sizeof flat;
  CHECK_EQ_INT(pb_hdr_decode(f, n, 100, 1000, &px, &w, &h, why, sizeof why), PB_OK);
  if (px) {
    CHECK_EQ_INT(w, 2);
    CHECK_EQ_INT(h, 2);
    CHECK_NEAR(px[0], rgbe(10, 130), 0);
    CHECK_NEAR(px[4], rgbe(0, 120), 0);
    CHECK_NEAR(px[3 * 3 + 2], rgbe(9, 129), 0); /* the run copied pixel (0, 1) */
    free(px);
  }
  /* +Y: the first line is the bottom row. */
  n = put(f, "#?RGBE\n\n+Y 2 +X 1\n");
  uint8_t up[] = {1, 2, 3, 128, 4, 5, 6, 128};
  memcpy(f + n, up, sizeof up);
  CHECK_EQ_INT(pb_hdr_decode(f, n + sizeof up, 100, 1000, &px, &w, &h, why, sizeof why), PB_OK);
  if (px) {
    CHECK_NEAR(px[0], rgbe(4, 128), 0);
    free(px);
  }
  /* New-style RLE, 10 pixels wide: R a run of 10 x 50, G literal 0..9,
   * B a run of 4 then 6 literals, E a run of 10 x 131. */
  n = put(f, "#?RADIANCE\n\n-Y 1 +X 10\n");
  uint8_t rle[] = {2, 2, 0, 10, 128 + 10, 50, 10, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9,
                   128 + 4, 7, 6, 1, 2, 3, 4, 5, 6, 128 + 10, 131};
  memcpy(f + n, rle, sizeof rle);
  CHECK_EQ_INT(pb_hdr_decode(f, n + sizeof rle, 100, 1000, &px, &w, &h, why, sizeof why), PB_OK);
  if (px) {
    CHECK_NEAR(px[3 * 9], rgbe(50, 131), 0);
    CHECK_NEAR(px[3 * 7 + 1], rgbe(7, 131), 0);
    CHECK_NEAR(px[3 * 2 + 2], rgbe(7, 131), 0);
    CHECK_NEAR(px[3 * 5 + 2], rgbe(2, 131), 0);
    free(px);
  }
  /* Malformed: each is PB_ERR_IMAGE with a reason. */
  struct {
    const char *what;
    size_t cut; /* bytes of rle[] kept */
    int edit;   /* index of rle[] changed */
    uint8_t to;
  } bad[] = {{"run past the line", sizeof rle, 4, 128 + 11},
             {"literal count 0", sizeof rle, 6, 0},
             {"line width", sizeof rle, 3, 11},
             {"truncated", 12, -1, 0},
             {"literals past the line", sizeof rle, 6, 11}};
  for (size_t i = 0; i < sizeof bad / sizeof *bad; ++i) {
    uint8_t r2[sizeof rle];
    memcpy(r2, rle, sizeof rle);
    if (bad[i].edit >= 0) r2[bad[i].edit] = bad[i].to;
    memcpy(f + n, r2, bad[i].cut);
    why[0] = 0;
    pb_result e = pb_hdr_decode(f, n + bad[i].cut, 100, 1000, &px, &w, &h, why, sizeof why);
    printf("hdr %-24s -> %d: %s\n", bad[i].what, e, why);
    CHECK_EQ_INT(e, PB_ERR_IMAGE);
    CHECK(px == NULL && why[0]);
  }
  n = put(f, "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n");
  CHECK_EQ_INT(pb_hdr_decode(f, n + 4, 100, 1000, &px, &w, &h, why, sizeof why), PB_ERR_IMAGE);
  n = put(f, "#?RADIANCE\n\n-Y 1 -X 1\n");
  CHECK_EQ_INT(pb_hdr_decode(f, n + 4, 100, 1000, &px, &w, &h, why, sizeof why), PB_ERR_IMAGE);
  n = put(f, "#?RADIANCE\n\n-Y 60000 +X 60000\n");
  CHECK_EQ_INT(pb_hdr_decode(f, n, 16384, 1u << 26, &px, &w, &h, why, sizeof why), PB_ERR_LIMIT);
  CHECK_EQ_INT(w, 60000);
  n = put(f, "#?RADIANCE\n-Y 1 +X 1\n");
  CHECK_EQ_INT(pb_hdr_decode(f, n, 100, 1000, &px, &w, &h, why, sizeof why), PB_ERR_IMAGE);
  CHECK_EQ_INT(pb_hdr_decode((const uint8_t *)"", 0, 100, 1000, &px, &w, &h, why, sizeof why), PB_ERR_IMAGE);
}

int main(void) {
  if (!mkdtemp(dir)) {
    perror("mkdtemp");
    return 1;
  }
  test_lights();
  test_world();
  test_hdr();
  rmdir(dir);
  return pbt_done();
}
