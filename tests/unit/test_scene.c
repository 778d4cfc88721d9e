/* The loader's semantics on small glTF files written by the test: node
 * transforms, winding under mirroring, flat normals, strips and fans, light
 * unit conversion (shared/VALIDATION.md), cameras, material classification;
 * loading from memory (pb_scene_load_memory: URIs, names in messages). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/fs.h"
#include "pbtest.h"
#include "gltf_test.h"
#include "scene/scene.h"

static char dir[] = "/tmp/pbtest_scene_XXXXXX";


/* One triangle (0,0,0) (1,0,0) (0,1,0), CCW seen from +Z, with normals +Z
 * (or none), as buffer 0 in a data URI; `nodes`, `extra` complete the file. */
static pb_result load_json(const char *nodes, const char *extra, int with_normals, const pb_load_desc *desc, pb_scene *s) {
  float v[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  char *data = pbt_b64(v, sizeof v);
  char path[256];
  snprintf(path, sizeof path, "%s/t.gltf", dir);
  FILE *f = fopen(path, "w");
  fprintf(f,
          "{\"asset\":{\"version\":\"2.0\"},"
          "\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,%s\",\"byteLength\":72}],"
          "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":36}],"
          "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
          "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],"
          "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0%s}}]}],"
          "\"nodes\":[%s],\"scenes\":[{\"nodes\":[0]}],\"scene\":0%s%s}",
          data, with_normals ? ",\"NORMAL\":1" : "", nodes, extra[0] ? "," : "", extra);
  fclose(f);
  free(data);
  pb_error_clear();
  pb_result r = pb_scene_load(path, desc, s);
  unlink(path);
  return r;
}

static void cross(const float *a, const float *b, const float *c, float n[3]) {
  float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

static void test_transforms(void) {
  pb_scene s;
  /* Parent translates (1,2,3); child rotates 90 degrees about Z and scales 2.
   * Vertex (1,0,0) -> scale (2,0,0) -> rotate (0,2,0) -> translate (1,4,3). */
  const char *nodes = "{\"translation\":[1,2,3],\"children\":[1]},"
                      "{\"mesh\":0,\"rotation\":[0,0,0.70710678,0.70710678],\"scale\":[2,2,2]}";
  CHECK_EQ_INT(load_json(nodes, "", 1, NULL, &s), PB_OK);
  CHECK_EQ_INT(s.triangle_count, 1);
  const float *p1 = s.positions[s.triangles[0][1]];
  CHECK_NEAR(p1[0], 1, 1e-6);
  CHECK_NEAR(p1[1], 4, 1e-6);
  CHECK_NEAR(p1[2], 3, 1e-6);
  CHECK_NEAR(s.normals[s.triangles[0][0]][2], 1, 1e-6); /* rotation about Z keeps +Z */
  CHECK_EQ_INT(s.camera_count, 1);                       /* synthesized */
  CHECK_EQ_INT(s.cameras[0].synthesized, 1);
  pb_scene_destroy(&s);

  /* The same through a matrix (column-major). */
  const char *mat = "{\"mesh\":0,\"matrix\":[0,2,0,0, -2,0,0,0, 0,0,2,0, 1,2,3,1]}";
  CHECK_EQ_INT(load_json(mat, "", 1, NULL, &s), PB_OK);
  p1 = s.positions[s.triangles[0][1]];
  CHECK(fabsf(p1[0] - 1) < 1e-6f && fabsf(p1[1] - 4) < 1e-6f && fabsf(p1[2] - 3) < 1e-6f);
  pb_scene_destroy(&s);

  /* Mirroring (negative scale) flips the winding so that the geometric normal
   * from the winding still agrees with the (transformed) shading normal. */
  for (int with_normals = 0; with_normals < 2; ++with_normals) {
    const char *neg[] = {"{\"mesh\":0,\"scale\":[-1,1,1]}", "{\"mesh\":0,\"scale\":[1,1,-1]}",
                         "{\"mesh\":0,\"scale\":[-1,-1,-1]}", "{\"mesh\":0,\"scale\":[1,1,1]}"};
    for (int k = 0; k < 4; ++k) {
      CHECK_EQ_INT(load_json(neg[k], "", with_normals, NULL, &s), PB_OK);
      const uint32_t *t = s.triangles[0];
      float g[3];
      cross(s.positions[t[0]], s.positions[t[1]], s.positions[t[2]], g);
      const float *n = s.normals[t[0]];
      CHECK(g[0] * n[0] + g[1] * n[1] + g[2] * n[2] > 0.99f * sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]));
      /* And the normal is the mirrored +Z: -Z exactly when z is mirrored. */
      CHECK_NEAR(n[2], (k == 1 || k == 2) ? -1 : 1, 1e-6);
      pb_scene_destroy(&s);
    }
  }
}

static void test_lights_and_cameras(void) {
  pb_scene s;
  const char *nodes =
      "{\"mesh\":0},"
      "{\"name\":\"Lamp\",\"translation\":[0,5,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
      "{\"name\":\"Spot\",\"rotation\":[-0.70710678,0,0,0.70710678],\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}},"
      "{\"name\":\"Sun\",\"rotation\":[-0.70710678,0,0,0.70710678],\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}},"
      "{\"name\":\"Cam\",\"translation\":[0,0,10],\"camera\":0}";
  const char *extra =
      "\"extensionsUsed\":[\"KHR_lights_punctual\"],"
      "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":["
      "{\"type\":\"point\",\"intensity\":683,\"color\":[1,0.5,0.25]},"
      "{\"type\":\"spot\",\"intensity\":1366,\"spot\":{\"innerConeAngle\":0.2,\"outerConeAngle\":0.4}},"
      "{\"type\":\"directional\",\"intensity\":3415}]}},"
      "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.5,\"aspectRatio\":1.5,\"znear\":0.1}}]";
  pb_load_desc d = {0};
  /* Only node 0 is listed in the scene: the others are not shown. */
  CHECK_EQ_INT(load_json(nodes, extra, 1, &d, &s), PB_OK);
  CHECK_EQ_INT(s.light_count, 0);
  pb_scene_destroy(&s);

  /* All nodes under one root. */
  const char *fix = "{\"children\":[1,2,3,4,5]},"
                    "{\"mesh\":0},"
                    "{\"name\":\"Lamp\",\"translation\":[0,5,0],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
                    "{\"name\":\"Spot\",\"rotation\":[-0.70710678,0,0,0.70710678],\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}},"
                    "{\"name\":\"Sun\",\"rotation\":[-0.70710678,0,0,0.70710678],\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}},"
                    "{\"name\":\"Cam\",\"translation\":[0,0,10],\"camera\":0}";
  CHECK_EQ_INT(load_json(fix, extra, 1, &d, &s), PB_OK);
  CHECK_EQ_INT(s.light_count, 3);
  if (s.light_count == 3) {
    /* Standard (photometric): W/sr = cd / 683, W/m^2 = lx / 683. */
    CHECK(strcmp(s.lights[0].name, "Lamp") == 0);
    CHECK_EQ_INT(s.lights[0].type, PB_LIGHT_POINT);
    CHECK_NEAR(s.lights[0].intensity, 1.0, 1e-6);
    CHECK_NEAR(s.lights[0].file_intensity, 683.0, 1e-3);
    CHECK_NEAR(s.lights[0].position[1], 5.0, 1e-6);
    CHECK_NEAR(s.lights[0].color[1], 0.5, 1e-6);
    CHECK_EQ_INT(s.lights[1].type, PB_LIGHT_SPOT);
    CHECK_NEAR(s.lights[1].intensity, 2.0, 1e-6);
    CHECK_NEAR(s.lights[1].inner_cone, 0.2, 1e-6);
    CHECK_NEAR(s.lights[1].outer_cone, 0.4, 1e-6);
    /* -90 degrees about X turns -Z into -Y: the spot points down. */
    CHECK_NEAR(s.lights[1].direction[1], -1.0, 1e-6);
    CHECK_EQ_INT(s.lights[2].type, PB_LIGHT_DIRECTIONAL);
    CHECK_NEAR(s.lights[2].intensity, 5.0, 1e-5);
    CHECK_NEAR(s.lights[2].direction[1], -1.0, 1e-6);
    /* Point light power 4 pi I. */
    float pw[3];
    pb_light_power(&s.lights[0], 1, pw);
    CHECK_NEAR(pw[0], 4 * M_PI, 1e-4);
  }
  CHECK_EQ_INT(s.camera_count, 1);
  if (s.camera_count == 1) {
    const pb_camera *c = &s.cameras[0];
    CHECK(strcmp(c->name, "Cam") == 0);
    CHECK_EQ_INT(c->synthesized, 0);
    CHECK_NEAR(c->position[2], 10, 1e-6);
    CHECK_NEAR(c->forward[2], -1, 1e-6);
    CHECK_NEAR(c->up[1], 1, 1e-6);
    CHECK_NEAR(c->right[0], 1, 1e-6);
    CHECK_NEAR(c->yfov, 0.5, 1e-6);
    CHECK_NEAR(c->aspect, 1.5, 1e-6);
    CHECK_EQ_INT(pb_scene_find_camera(&s, "Cam"), 0);
    CHECK_EQ_INT(pb_scene_find_camera(&s, "Nope"), -1);
  }
  pb_scene_destroy(&s);

  /* Unitless: the file's values are already W/sr and W/m^2. */
  d.light_units = PB_LIGHT_UNITS_UNITLESS;
  CHECK_EQ_INT(load_json(fix, extra, 1, &d, &s), PB_OK);
  if (s.light_count == 3) {
    CHECK_NEAR(s.lights[0].intensity, 683.0, 1e-3);
    CHECK_NEAR(s.lights[2].intensity, 3415.0, 1e-2);
  }
  pb_scene_destroy(&s);
}

static void test_materials(void) {
  pb_scene s;
  const char *extra =
      "\"materials\":["
      "{\"name\":\"diffuse\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.8,0.2,0.1,1],\"metallicFactor\":0,\"roughnessFactor\":1},"
      " \"extensions\":{\"KHR_materials_specular\":{\"specularColorFactor\":[0,0,0]}}},"
      "{\"name\":\"mirror\",\"pbrMetallicRoughness\":{\"metallicFactor\":1,\"roughnessFactor\":0}},"
      "{\"name\":\"glass\",\"pbrMetallicRoughness\":{\"metallicFactor\":0,\"roughnessFactor\":0},"
      " \"extensions\":{\"KHR_materials_transmission\":{\"transmissionFactor\":1},\"KHR_materials_ior\":{\"ior\":1.33}}},"
      "{\"name\":\"lamp\",\"emissiveFactor\":[1,0.5,0],\"extensions\":{\"KHR_materials_emissive_strength\":{\"emissiveStrength\":10}}}]";
  CHECK_EQ_INT(load_json("{\"mesh\":0}", extra, 1, NULL, &s), PB_OK);
  CHECK_EQ_INT(s.material_count, 5); /* four + glTF's default for the unassigned primitive */
  if (s.material_count == 5) {
    CHECK_EQ_INT(pb_material_kind(&s.materials[0]), PB_BSDF_DIFFUSE);
    /* specularColorFactor 0: the whole layer goes, F90 included. */
    CHECK_NEAR(s.materials[0].specular, 0, 0);
    CHECK_NEAR(s.materials[1].specular, 1, 0); /* no extension: the default layer */
    CHECK_NEAR(s.materials[0].base_color[0], 0.8, 1e-6);
    CHECK_EQ_INT(pb_material_kind(&s.materials[1]), PB_BSDF_MIRROR);
    CHECK_EQ_INT(pb_material_kind(&s.materials[2]), PB_BSDF_GLASS);
    CHECK_NEAR(s.materials[2].ior, 1.33, 1e-6);
    CHECK_NEAR(s.materials[3].emissive[0], 10, 1e-5);
    CHECK_NEAR(s.materials[3].emissive[1], 5, 1e-5);
    CHECK(strcmp(s.materials[4].name, "(glTF default)") == 0);
    CHECK_NEAR(s.materials[4].metallic, 1, 0);
    CHECK_EQ_INT(s.triangle_material[0], 4);
  }
  /* Features count only materials in use: the default (rough metal) one. */
  CHECK_EQ_INT(s.features, PB_FEATURE_GLOSSY);
  pb_scene_destroy(&s);
}

/* pb_scene_load_memory: a sample with an external buffer (resolved against
 * the folder given, refused without one), a data-URI file without a folder,
 * and a checking error naming the caller's name. */
static void test_memory(void) {
  const char *path = "samples/cornell_box/cornell_box.gltf";
  uint8_t *bytes = NULL;
  size_t n = 0;
  CHECK(pb_read_file(path, 1u << 26, &bytes, &n) == PB_OK);
  if (!bytes) return;
  pb_scene a, b;
  CHECK(pb_scene_load(path, NULL, &a) == PB_OK);
  CHECK(pb_scene_load_memory("cornell (memory)", "samples/cornell_box", bytes, n, NULL, &b) == PB_OK);
  CHECK_EQ_INT(a.vertex_count, b.vertex_count);
  CHECK_EQ_INT(a.triangle_count, b.triangle_count);
  CHECK_EQ_INT(a.material_count, b.material_count);
  CHECK_EQ_INT(a.light_count, b.light_count);
  CHECK(a.vertex_count > 0 && !memcmp(a.positions, b.positions, (size_t)a.vertex_count * sizeof *a.positions));
  CHECK(b.path && strcmp(b.path, "cornell (memory)") == 0);
  pb_scene_destroy(&a);
  pb_scene_destroy(&b);
  /* No folder: the external buffer is refused, naming the input and the element. */
  pb_error_clear();
  CHECK_EQ_INT(pb_scene_load_memory("mem.gltf", NULL, bytes, n, NULL, &b), PB_ERR_SCENE_UNSUPPORTED);
  CHECK(strncmp(pb_error_message(), "mem.gltf: buffers[0].uri: 'cornell_box.bin': ", 45) == 0);
  CHECK(!strchr(pb_error_message(), '\n'));
  free(bytes);
  /* No name: "<memory>" stands for the input. */
  pb_error_clear();
  CHECK_EQ_INT(pb_scene_load_memory(NULL, "samples/ring", "{}", 2, NULL, &b), PB_ERR_SCENE_INVALID);
  CHECK(strncmp(pb_error_message(), "<memory>: asset: missing", 24) == 0);

  /* Data URIs need no folder. */
  float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  char *data = pbt_b64(v, sizeof v);
  char json[1024];
  for (int bad = 0; bad < 2; ++bad) {
    snprintf(json, sizeof json,
             "{\"asset\":{\"version\":\"2.0\"},"
             "\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,%s\",\"byteLength\":36}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],"
             "\"materials\":[{\"alphaMode\":\"%s\"}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"material\":0}]}],"
             "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]}",
             data, bad ? "CLEAR" : "OPAQUE");
    pb_error_clear();
    pb_result r = pb_scene_load_memory("inline.gltf", NULL, json, strlen(json), NULL, &b);
    if (!bad) {
      CHECK_EQ_INT(r, PB_OK);
      CHECK_EQ_INT(b.triangle_count, 1);
      pb_scene_destroy(&b);
    } else {
      CHECK_EQ_INT(r, PB_ERR_SCENE_INVALID);
      CHECK(strcmp(pb_error_message(), "inline.gltf: materials[0].alphaMode: 'CLEAR' is not OPAQUE, MASK or BLEND") == 0);
      static const pb_scene zero;
      CHECK(!memcmp(&b, &zero, sizeof b));
    }
  }
  free(data);
}

/* The kinds' table (scene/light.h): the host's kind is the GPU's value,
 * every kind has a row, and the readers' type names parse to it. */
static void test_light_kinds(void) {
  CHECK_EQ_INT(PB_LIGHT_SPOT, PB_GPU_LIGHT_SPOT);
  CHECK_EQ_INT(PB_LIGHT_AREA, PB_GPU_LIGHT_AREA);
  for (int t = 0; t < PB_LIGHT_KIND_COUNT; ++t) {
    const pb_light_kind *k = pb_light_kind_of((pb_light_type)t);
    CHECK(k && k->name && k->blender_type && k->power && k->pack && k->describe && k->json && k->emission);
  }
  CHECK(pb_light_kind_of(PB_LIGHT_KIND_COUNT) == NULL);
  CHECK(strcmp(pb_light_kind_name(PB_LIGHT_KIND_COUNT), "unknown") == 0);
  pb_light_type t = PB_LIGHT_POINT;
  char known[64];
  CHECK_EQ_INT(pb_light_kind_parse("directional", 0, &t, known, sizeof known), 1);
  CHECK_EQ_INT(t, PB_LIGHT_DIRECTIONAL);
  CHECK(strcmp(known, "point, spot or directional") == 0);
  CHECK_EQ_INT(pb_light_kind_parse("area", 0, &t, NULL, 0), 0); /* not in KHR_lights_punctual */
  CHECK_EQ_INT(pb_light_kind_parse("AREA", 1, &t, known, sizeof known), 1);
  CHECK_EQ_INT(t, PB_LIGHT_AREA);
  CHECK(strcmp(known, "POINT, SPOT, SUN or AREA") == 0);
  /* The GPU's light: the kind as it is, a spot's cone, an area's shape. */
  pb_light l;
  memset(&l, 0, sizeof l);
  l.type = PB_LIGHT_AREA;
  l.intensity = 2.0f;
  l.color[0] = l.color[1] = l.color[2] = 1.0f;
  l.direction[2] = -2.0f;
  l.size[0] = 2.0f;
  l.size[1] = 0.5f;
  l.shape = PB_AREA_ELLIPSE;
  pb_gpu_light g;
  pb_light_pack_gpu(&l, &g);
  CHECK_EQ_INT(g.type, PB_GPU_LIGHT_AREA);
  CHECK_NEAR(g.direction[2], -1.0, 1e-6);
  CHECK_NEAR(g.power[1], 2.0, 1e-6);
  CHECK(g.flags & PB_GPU_LIGHT_ELLIPSE);
  CHECK_NEAR(g.size_u, 2.0, 1e-6);
  CHECK_NEAR(g.norm_spread, 1.0, 1e-6); /* spread pi: Lambertian */
  CHECK_EQ_INT(pb_light_is_delta(&l), 0);
  float v;
  CHECK(pb_light_softness(&l, &v) == NULL);
  l.type = PB_LIGHT_SPOT;
  l.outer_cone = 0.5f;
  l.radius = 0.25f;
  pb_light_pack_gpu(&l, &g);
  CHECK_EQ_INT(g.type, PB_GPU_LIGHT_SPOT);
  CHECK_NEAR(g.cos_outer, cos(0.5), 1e-6);
  CHECK_NEAR(g.radius, 0.25, 1e-6);
  CHECK(strcmp(pb_light_softness(&l, &v), "radius") == 0 && v == 0.25f);
  CHECK_EQ_INT(pb_light_is_delta(&l), 0);
  l.type = PB_LIGHT_DIRECTIONAL;
  l.angle = 0.0f;
  CHECK_EQ_INT(pb_light_is_delta(&l), 1);
  CHECK(strcmp(pb_light_softness(&l, &v), "angle") == 0);
}

int main(void) {
  if (!mkdtemp(dir)) return 1;
  test_transforms();
  test_lights_and_cameras();
  test_materials();
  test_memory();
  test_light_kinds();
  rmdir(dir);
  return pbt_done();
}
