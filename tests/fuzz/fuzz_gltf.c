/* libFuzzer target: the glTF/GLB loader (pb_scene_load_memory) on arbitrary
 * bytes.
 *
 * Each input is loaded from memory, named "fuzz_gltf-input.glb" when it
 * starts with the GLB magic "glTF" and "fuzz_gltf-input.gltf" otherwise (the
 * loader itself decides by the magic; the name is what messages must name). Its URIs resolve against the
 * target's folder (fuzz_util.h), which holds base.bin and tex.png from the
 * corpus (tests/corpus/valid/base), so that inputs referencing them reach
 * buffer and image decoding; nothing is written per input. A finding
 * reproduces with `photonbridge info` on the file saved next to those two.
 *
 * Besides memory errors and undefined behaviour (ASan + UBSan), the target
 * aborts when the loader breaks its contract (scene.h, docs/scenes.md):
 *   - failure: a code from the loader's set (never PB_ERR_INTERNAL, which
 *     the shim returns for a std::logic_error or json::exception: a check
 *     that read past what it tested), a one-line message that names the
 *     file, and an `out` with nothing in it;
 *   - success: every triangle index below vertex_count, every material and
 *     texture index in range, finite positions, textures with pixels.
 * A successful scene is then used the way renderers use it (texture lookups
 * at the file's UVs, light power, camera image size), so that values the
 * loader lets through are exercised too. Cameras, lights and material
 * factors must be finite floats.
 *
 * PB_FUZZ_VERBOSE=1 prints each input's result and message (reproducing:
 * PB_FUZZ_VERBOSE=1 build-fuzz/fuzz_gltf FILE). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fs.h"
#include "core/log.h"
#include "core/result.h"
#include "fuzz_util.h"
#include "scene/scene.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char *base_dir; /* the folder external URIs resolve against */

#define FAIL pb_fuzz_fail

static void copy_aux(const char *name) {
  char src[600];
  snprintf(src, sizeof src, "%s/%s", PB_FUZZ_AUX_DIR, name);
  uint8_t *d = NULL;
  size_t n = 0;
  if (pb_read_file(src, 1 << 20, &d, &n) != PB_OK) {
    pb_error_clear();
    return; /* the target still works without it */
  }
  pb_fuzz_write(pb_fuzz_path(name), d, n);
  free(d);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  pb_fuzz_init("gltf");
  base_dir = pb_dirname(pb_fuzz_path("base.bin"));
  if (!base_dir) FAIL("out of memory");
  copy_aux("base.bin");
  copy_aux("tex.png");
  return 0;
}

static void check_failure(const char *path, pb_result r, const pb_scene *s) {
  switch (r) {
  case PB_ERR_IO: case PB_ERR_SCENE_PARSE: case PB_ERR_SCENE_INVALID:
  case PB_ERR_SCENE_UNSUPPORTED: case PB_ERR_SCENE_EMPTY: case PB_ERR_IMAGE:
  case PB_ERR_LIMIT: case PB_ERR_NOMEM:
    break;
  default:
    FAIL("pb_scene_load_memory returned %d (%s)", (int)r, pb_error_message());
  }
  const char *msg = pb_error_message();
  if (!msg || !msg[0]) FAIL("failure %d without a message", (int)r);
  if (strchr(msg, '\n') || strchr(msg, '\r')) FAIL("message is not one line: %s", msg);
  if (!strstr(msg, path)) FAIL("message does not name the file: %s", msg);
  if (!pb_fuzz_all_zero(s, sizeof *s)) FAIL("failure %d left a non-empty scene (%s)", (int)r, msg);
}

static void check_tex(const pb_scene *s, int32_t t, const char *what, uint32_t m) {
  if (t != PB_NO_TEXTURE && (t < 0 || (uint32_t)t >= s->texture_count))
    FAIL("materials[%u].%s: texture %d of %u", m, what, t, s->texture_count);
}

static volatile float sink;

static void check_success(const pb_scene *s) {
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    for (int c = 0; c < 3; ++c)
      if (s->triangles[t][c] >= s->vertex_count)
        FAIL("triangle %u: vertex %u of %u", t, s->triangles[t][c], s->vertex_count);
    if (s->triangle_material[t] >= s->material_count)
      FAIL("triangle %u: material %u of %u", t, s->triangle_material[t], s->material_count);
  }
  for (uint32_t v = 0; v < s->vertex_count; ++v)
    for (int c = 0; c < 3; ++c)
      if (!isfinite(s->positions[v][c])) FAIL("vertex %u: position is not finite", v);
  /* COLOR_0 in [0, 1], TEXCOORD_1 finite (scene.h). */
  for (uint32_t v = 0; s->colors && v < s->vertex_count; ++v)
    for (int c = 0; c < 4; ++c)
      if (!(s->colors[v][c] >= 0 && s->colors[v][c] <= 1)) FAIL("vertex %u: colour %g is not in [0, 1]", v, s->colors[v][c]);
  for (uint32_t v = 0; s->uvs1 && v < s->vertex_count; ++v)
    if (!isfinite(s->uvs1[v][0]) || !isfinite(s->uvs1[v][1])) FAIL("vertex %u: TEXCOORD_1 is not finite", v);
  for (uint32_t c = 0; c < s->camera_count; ++c) {
    const pb_camera *k = &s->cameras[c];
    for (int i = 0; i < 3; ++i)
      if (!isfinite(k->position[i]) || !isfinite(k->forward[i]) || !isfinite(k->up[i]) || !isfinite(k->right[i]))
        FAIL("cameras[%u]: position or frame is not finite", c);
    /* scene/camera.h: perspective yfov in (0, pi) or a positive orthographic
     * size; clip planes 0 <= znear < zfar (zfar 0: none); finite shift. */
    int proj_ok = k->orthographic ? k->ortho_size > 0 && isfinite(k->ortho_size) : k->yfov > 0 && k->yfov < 3.1416f;
    if (!proj_ok || !(k->znear >= 0) || !isfinite(k->znear) || !isfinite(k->zfar) ||
        (k->zfar != 0 && !(k->zfar > k->znear)) || !isfinite(k->shift[0]) || !isfinite(k->shift[1]) ||
        !isfinite(k->aspect) || k->aspect < 0)
      FAIL("cameras[%u]: yfov %g ortho %g znear %g zfar %g aspect %g", c, k->yfov, k->ortho_size, k->znear, k->zfar,
           k->aspect);
  }
  for (uint32_t l = 0; l < s->light_count; ++l) {
    const pb_light *g = &s->lights[l];
    for (int i = 0; i < 3; ++i)
      if (!isfinite(g->position[i]) || !isfinite(g->direction[i]) || !isfinite(g->color[i]) || g->color[i] < 0)
        FAIL("lights[%u]: position, direction or colour is not finite", l);
    if (!isfinite(g->intensity) || g->intensity < 0 || !isfinite(g->file_intensity) || !isfinite(g->range) ||
        !isfinite(g->inner_cone) ||
        !isfinite(g->outer_cone))
      FAIL("lights[%u]: intensity %g range %g cones %g %g", l, g->intensity, g->range, g->inner_cone, g->outer_cone);
  }
  for (uint32_t m = 0; m < s->material_count; ++m) {
    const pb_material *mt = &s->materials[m];
    const float f[] = {mt->base_color[0], mt->base_color[1], mt->base_color[2], mt->base_color[3], mt->metallic,
                       mt->roughness, mt->specular, mt->specular_color[0], mt->specular_color[1],
                       mt->specular_color[2], mt->emissive[0], mt->emissive[1], mt->emissive[2], mt->transmission,
                       mt->ior, mt->normal_scale, mt->alpha_cutoff};
    for (size_t i = 0; i < sizeof f / sizeof *f; ++i)
      if (!isfinite(f[i])) FAIL("materials[%u]: factor %zu is not finite", m, i);
    check_tex(s, mt->base_color_tex, "base_color_tex", m);
    check_tex(s, mt->metallic_roughness_tex, "metallic_roughness_tex", m);
    check_tex(s, mt->emissive_tex, "emissive_tex", m);
    check_tex(s, mt->normal_tex, "normal_tex", m);
    sink += (float)pb_material_kind(mt) + (float)pb_material_is_emissive(mt);
  }
  for (uint32_t t = 0; t < s->texture_count; ++t) {
    const pb_texture *tx = &s->textures[t];
    if (!tx->rgba8 || !tx->width || !tx->height) FAIL("textures[%u]: %ux%u without pixels", t, tx->width, tx->height);
    /* Corners (touches the whole allocation's ends) and the file's UVs. */
    sink += tx->rgba8[0] + tx->rgba8[(size_t)tx->width * tx->height * 4 - 1];
    float out[4];
    uint32_t n = s->vertex_count < 64 ? s->vertex_count : 64;
    for (uint32_t v = 0; v < n; ++v) {
      pb_texture_sample(tx, s->uvs[v][0], s->uvs[v][1], out);
      sink += out[0] + out[3];
    }
    pb_texture_sample(tx, -1e30f, 1e30f, out);
    sink += out[1];
  }
  float r = 0;
  for (int c = 0; c < 3; ++c) {
    float e = s->bounds_max[c] - s->bounds_min[c];
    r += e * e;
  }
  r = sqrtf(r) * 0.5f;
  for (uint32_t l = 0; l < s->light_count; ++l) {
    float p[3];
    pb_light_power(&s->lights[l], r, p);
    sink += p[0];
  }
  for (uint32_t c = 0; c < s->camera_count; ++c) {
    uint32_t w = 0, h = 0;
    pb_camera_image_size(&s->cameras[c], 0, 0, &w, &h);
    if (!w || !h) FAIL("cameras[%u]: image size %ux%u", c, w, h);
  }
  if (s->camera_count && pb_scene_find_camera(s, NULL) != 0) FAIL("first camera not found");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const char *path = size >= 4 && memcmp(data, "glTF", 4) == 0 ? "fuzz_gltf-input.glb" : "fuzz_gltf-input.gltf";
  /* Limits below the defaults keep every run inside libFuzzer's 2 GB
   * allocation limit (the defaults allow a 64 M triangle scene); the code
   * paths are the same. */
  pb_load_desc desc = {.max_file_bytes = 16u << 20, .max_image_dim = 2048,
                       .max_image_pixels = 1u << 20, .max_triangles = 1u << 20};
  pb_scene s;
  pb_error_clear();
  pb_result r = pb_scene_load_memory(path, base_dir, data, size, &desc, &s);
  if (pb_fuzz_verbose()) fprintf(stderr, "fuzz_gltf: %s: result %d: %s\n", path, (int)r, r ? pb_error_message() : "ok");
  if (r != PB_OK) {
    check_failure(path, r, &s);
  } else {
    check_success(&s);
    /* Poses (node animation, skins, morph weights) at the start, the middle
     * and the end: PB_OK with the same contract, or a one-line
     * PB_ERR_SCENE_INVALID naming the file (a pose out of float range). */
    for (int k = 0; s.anim && k < 3; ++k) {
      pb_error_clear();
      double t = s.anim_start + 0.5 * k * (s.anim_end - s.anim_start);
      pb_result pr = pb_scene_set_time(&s, t);
      if (pr == PB_OK) {
        check_success(&s);
        continue;
      }
      const char *msg = pb_error_message();
      if (pr != PB_ERR_SCENE_INVALID || !strstr(msg, path) || strchr(msg, '\n'))
        FAIL("pb_scene_set_time(%g) returned %d: %s", t, (int)pr, msg);
      break;
    }
    pb_scene_destroy(&s);
  }
  pb_error_clear();
  return 0;
}
