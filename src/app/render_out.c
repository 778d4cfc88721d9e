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

static int reliability_warned;

void pb_render_warn_reset(void) { reliability_warned = 0; }

void pb_render_warn_reliability(const char *cmd, const pb_render_stats *st) {
  int *warned = &reliability_warned;
  double miss_rate = pb_render_image_miss_rate(st);
  if (*warned || !(miss_rate > PB_RENDER_IMAGE_MISS_WARN)) return;
  *warned = 1;
  pb_log_warn("%s: the environment-map photon tracer (--tracer images) found no surface for %.0f %% of its photon "
              "segments (--json photons.image_miss_rate): the indirect light may leak past geometry no map sees "
              "(thin or hidden surfaces); --tracer bvh traces them exactly", cmd, 100.0 * miss_rate);
}
