/* What `photonbridge render` writes, shared by a single frame (cmd_render.c)
 * and a sequence (cmd_render_seq.c): the multilayer EXR of a frame's AOVs,
 * in photonbridge's channel names or Blender's, the refining previews, and
 * the machine-readable progress lines the Blender add-on reads. */
#ifndef PB_APP_RENDER_OUT_H
#define PB_APP_RENDER_OUT_H

#include <stdint.h>

#include "core/result.h"
#include "render/render.h"
#include "render/frame/result_exr.h" /* the frame's EXR: render_out writes it */

/* The format of render's -o OUT, from its extension (case-insensitive):
 * .exr the multilayer EXR above, .png the display-referred beauty through
 * the OCIO view (as --png). Any other name: PB_ERR_USAGE naming the
 * extension and the accepted ones. */
typedef enum pb_render_out_format { PB_RENDER_OUT_EXR, PB_RENDER_OUT_PNG } pb_render_out_format;
pb_result pb_render_out_format_of(const char *path, pb_render_out_format *fmt);

/* The progress a person reads on stderr (core/log.h's pb_progress): one
 * redrawn line on a terminal, a plain line at most every few seconds
 * otherwise, nothing with -q or with --progress-lines (whose reader wants
 * its own lines alone). Stages: "loading scene", "building BVH", "photon map
 * k/N", "frame i/N", "writing OUT"; eta_s < 0: unknown. */
void pb_render_bar_begin(int on);
void pb_render_bar_stage(const char *stage, uint64_t done, uint64_t total, double eta_s);
void pb_render_bar_end(void);


/* One progress line on stderr for programs that drive photonbridge (the
 * Blender add-on): "photonbridge progress: " and a one-line JSON object
 * whose "event" says what happened:
 *   {"event": "stage", "stage": "loaded" | "uploaded", "elapsed_s": t}
 *   {"event": "iteration", "iteration": k, "iterations": K, "samples": s,
 *    "spp": S, "elapsed_s": t, "preview": PATH | null}
 *   {"event": "frame", "frame": f, "index": i, "frames": n, "output": PATH}
 *   {"event": "done", "output": PATH, "elapsed_s": t}
 * Strings are JSON-escaped. Nothing is printed unless enabled (render
 * --progress-lines). */
/* --json "estimator": {"name": ..., its named statistics} of a frame
 * (pb_render_stats.estimator, estimator_stats; render/estimate/estimator.h); nothing
 * when the photon stages were off. */
struct pb_json;
void pb_render_json_estimator(struct pb_json *j, const pb_render_stats *st);

/* A method's own signal that it may have failed, as a warning after a frame
 * (cmd: "render"): the environment-map photon tracer (--tracer images)
 * missing more than PB_RENDER_IMAGE_MISS_WARN of its photon segments (light
 * then leaks past geometry no map sees; bench/README.md: 0.01 on spot_room,
 * 0.21 on sun_atrium, whose indirect light is 0.26 relMSE off). Once per
 * render command (a sequence's frames warn once); pb_render_warn_reset
 * starts a command (each job of `batch`). */
#define PB_RENDER_IMAGE_MISS_WARN 0.15
void pb_render_warn_reliability(const char *cmd, const pb_render_stats *st);
void pb_render_warn_reset(void);

void pb_progress_lines_enable(int on);
int pb_progress_lines_enabled(void);
void pb_progress_line_stage(const char *stage, double elapsed_s);
void pb_progress_line_iteration(const pb_render_progress *p, const char *preview);
void pb_progress_line_frame(int32_t frame, uint32_t index, uint32_t frames, const char *output);
void pb_progress_line_done(const char *output, double elapsed_s);

#endif
