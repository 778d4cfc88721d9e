/* A frame's AOVs as a multilayer EXR (result_exr.h). */
#include "render/frame/result_exr.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/image.h"

/* Cycles' depth for rays that hit nothing (its Depth pass background). */
#define BLENDER_DEPTH_MISS 1e10f

static const char *const blender_pass[] = {"Combined", "Depth", "Normal", "Emit", "Direct", "Indirect", "Caustic",
                                           "Albedo"};
enum { BLENDER_PASSES = sizeof blender_pass / sizeof *blender_pass };

/* Whether `name` is in the comma-separated `list` (NULL: every pass). */
static int listed(const char *list, const char *name) {
  if (!list) return 1;
  size_t n = strlen(name);
  for (const char *p = list; *p;) {
    const char *e = strchr(p, ',');
    size_t len = e ? (size_t)(e - p) : strlen(p);
    if (len == n && strncmp(p, name, n) == 0) return 1;
    p += len + (e ? 1 : 0);
  }
  return 0;
}

pb_result pb_render_check_blender_passes(const char *list) {
  if (!list) return PB_OK;
  for (const char *p = list; *p;) {
    const char *e = strchr(p, ',');
    size_t len = e ? (size_t)(e - p) : strlen(p);
    int ok = 0;
    for (int i = 0; i < BLENDER_PASSES; ++i) ok |= strlen(blender_pass[i]) == len && !strncmp(p, blender_pass[i], len);
    if (!ok)
      return pb_fail(PB_ERR_USAGE, "render: --blender-passes: '%.*s' is not one of Combined, Depth, Normal, Emit, "
                     "Direct, Indirect, Caustic, Albedo", (int)len, p);
    p += len + (e ? 1 : 0);
  }
  return PB_OK;
}

pb_result pb_render_write_exr(const char *path, const pb_render_result *res, const char *blender_layer,
                              const char *blender_passes, const char *const *attr_names,
                              const char *const *attr_values, uint32_t attr_count) {
  pb_exr_desc ed = {.width = res->width, .height = res->height, .attr_names = attr_names,
                    .attr_values = attr_values, .attr_count = attr_count};
  if (!blender_layer) {
    const pb_image_layer layers[] = {
        {"", 4, res->beauty, NULL},         {"direct", 3, res->direct, NULL}, {"albedo", 3, res->albedo, NULL},
        {"normal", 3, res->normal, NULL},   {"depth", 1, res->depth, NULL},   {"material", 1, res->material, NULL},
        {"emission", 3, res->emission, NULL},
        {"indirect", 3, res->indirect, NULL}, {"caustic", 3, res->caustic, NULL},
        /* Scenes with normal maps: seed 001 eq. 20's inputs (render.h). */
        {"geo_normal", 3, res->geo_normal, NULL}, {"photon_dir", 3, res->photon_dir, NULL},
    };
    uint32_t n = 1;
    if (res->direct) n = res->indirect ? (res->geo_normal ? 11 : 9) : 7;
    ed.layers = layers;
    ed.layer_count = n;
    return pb_exr_write(path, &ed);
  }
  /* Blender's names: LAYER.PASS.CHANNEL, channel letters of the pass's
   * chan_id (RGBA, Z, XYZ, RGB) as RE_render_result_full_channel_name makes
   * them. */
  size_t n = (size_t)res->width * res->height;
  float *zero = calloc(3 * n, sizeof(float)), *depth = malloc(n * sizeof(float));
  if (!zero || !depth) {
    free(zero);
    free(depth);
    return pb_fail(PB_ERR_NOMEM, "render: out of memory for %s", path);
  }
  for (size_t i = 0; i < n; ++i)
    depth[i] = res->depth && res->beauty[4 * i + 3] > 0 ? res->depth[i] : BLENDER_DEPTH_MISS;
  static const char *const chans[BLENDER_PASSES] = {"RGBA", "Z", "XYZ", "RGB", "RGB", "RGB", "RGB", "RGB"};
  const float *px[BLENDER_PASSES] = {res->beauty, depth, res->normal, res->emission, res->direct, res->indirect,
                                     res->caustic, res->albedo};
  char names[BLENDER_PASSES][4][64];
  const char *name_ptr[BLENDER_PASSES][4];
  pb_image_layer layers[BLENDER_PASSES];
  uint32_t count = 0;
  for (int p = 0; p < BLENDER_PASSES; ++p) {
    if (!listed(blender_passes, blender_pass[p])) continue;
    uint32_t ch = (uint32_t)strlen(chans[p]);
    for (uint32_t c = 0; c < ch; ++c) {
      snprintf(names[p][c], sizeof names[p][c], "%s.%s.%c", blender_layer, blender_pass[p], chans[p][c]);
      name_ptr[p][c] = names[p][c];
    }
    layers[count++] = (pb_image_layer){blender_pass[p], ch, px[p] ? px[p] : zero, name_ptr[p]};
  }
  ed.layers = layers;
  ed.layer_count = count;
  pb_result r = pb_exr_write(path, &ed);
  free(zero);
  free(depth);
  return r;
}

