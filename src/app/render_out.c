/* render's outputs (render_out.h). */
#include "app/render_out.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/json.h"
#include "core/log.h"
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

pb_result pb_render_out_format_of(const char *path, pb_render_out_format *fmt) {
  const char *slash = strrchr(path, '/');
  const char *base = slash ? slash + 1 : path;
  const char *dot = strrchr(base, '.');
  if (dot && !strcasecmp(dot, ".exr")) {
    *fmt = PB_RENDER_OUT_EXR;
    return PB_OK;
  }
  if (dot && !strcasecmp(dot, ".png")) {
    *fmt = PB_RENDER_OUT_PNG;
    return PB_OK;
  }
  if (!dot || dot == base)
    return pb_fail(PB_ERR_USAGE, "render: -o %s: no file extension; accepted: .exr (scene-linear, every pass) or "
                   ".png (display-referred through the OCIO view)", path);
  return pb_fail(PB_ERR_USAGE, "render: -o %s: unknown extension '%s'; accepted: .exr (scene-linear, every pass) "
                 "or .png (display-referred through the OCIO view)", path, dot);
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

/* ---- the progress bar ---------------------------------------------------------- */

static pb_progress bar;
static int bar_on;

void pb_render_bar_begin(int on) {
  bar_on = on;
  if (on) pb_progress_begin(&bar, "render", 0);
}

void pb_render_bar_stage(const char *stage, uint64_t done, uint64_t total, double eta_s) {
  if (bar_on) pb_progress_stage(&bar, stage, done, total, eta_s);
}

void pb_render_bar_end(void) {
  if (bar_on) pb_progress_end(&bar);
  bar_on = 0;
}

/* ---- progress lines ---------------------------------------------------------- */

static int lines_on;

void pb_progress_lines_enable(int on) { lines_on = on; }
int pb_progress_lines_enabled(void) { return lines_on; }

/* A JSON string literal of s (quotes, backslashes and control characters
 * escaped) on f. */
static void json_string(FILE *f, const char *s) {
  if (!s) {
    fputs("null", f);
    return;
  }
  fputc('"', f);
  for (const unsigned char *p = (const unsigned char *)s; *p; ++p) {
    if (*p == '"' || *p == '\\') fprintf(f, "\\%c", *p);
    else if (*p < 0x20) fprintf(f, "\\u%04x", *p);
    else fputc(*p, f);
  }
  fputc('"', f);
}

void pb_progress_line_stage(const char *stage, double elapsed_s) {
  if (!lines_on) return;
  fprintf(stderr, "photonbridge progress: {\"event\": \"stage\", \"stage\": ");
  json_string(stderr, stage);
  fprintf(stderr, ", \"elapsed_s\": %.3f}\n", elapsed_s);
  fflush(stderr);
}

void pb_progress_line_iteration(const pb_render_progress *p, const char *preview) {
  if (!lines_on) return;
  fprintf(stderr,
          "photonbridge progress: {\"event\": \"iteration\", \"iteration\": %u, \"iterations\": %u, \"samples\": %u, "
          "\"spp\": %u, \"elapsed_s\": %.3f, \"preview\": ",
          p->iteration, p->iterations, p->samples, p->spp, p->elapsed_s);
  json_string(stderr, preview);
  fprintf(stderr, "}\n");
  fflush(stderr);
}

void pb_progress_line_frame(int32_t frame, uint32_t index, uint32_t frames, const char *output) {
  if (!lines_on) return;
  fprintf(stderr, "photonbridge progress: {\"event\": \"frame\", \"frame\": %" PRId32 ", \"index\": %u, \"frames\": %u, "
                  "\"output\": ", frame, index, frames);
  json_string(stderr, output);
  fprintf(stderr, "}\n");
  fflush(stderr);
}

void pb_progress_line_done(const char *output, double elapsed_s) {
  if (!lines_on) return;
  fprintf(stderr, "photonbridge progress: {\"event\": \"done\", \"output\": ");
  json_string(stderr, output);
  fprintf(stderr, ", \"elapsed_s\": %.3f}\n", elapsed_s);
  fflush(stderr);
}

void pb_render_json_estimator(pb_json *j, const pb_render_stats *st) {
  if (!st->estimator) return;
  pb_json_begin_object(j, "estimator");
  pb_json_string(j, "name", st->estimator);
  for (uint32_t i = 0; i < st->estimator_stat_count; ++i)
    pb_json_number(j, st->estimator_stats[i].name, st->estimator_stats[i].value);
  pb_json_end_object(j);
}

void pb_render_warn_reliability(const char *cmd, const pb_render_stats *st) {
  static int warned;
  double segments = -1, misses = -1;
  for (uint32_t i = 0; i < st->tracer_stat_count; ++i) {
    if (!strcmp(st->tracer_stats[i].name, "image_segments")) segments = st->tracer_stats[i].value;
    if (!strcmp(st->tracer_stats[i].name, "image_misses")) misses = st->tracer_stats[i].value;
  }
  if (warned || !(segments > 0) || !(misses / segments > PB_RENDER_IMAGE_MISS_WARN)) return;
  warned = 1;
  pb_log_warn("%s: the environment-map photon tracer (--tracer images) found no surface for %.0f %% of its photon "
              "segments (--json photons.image_miss_rate): the indirect light may leak past geometry no map sees "
              "(thin or hidden surfaces); --tracer bvh traces them exactly", cmd, 100.0 * misses / segments);
}
