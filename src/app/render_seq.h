/* `photonbridge render --frames A:B`: the frame-sequence half of the render
 * subcommand (cmd_render.c parses the options; render/frame/sequence.h renders). */
#ifndef PB_APP_RENDER_SEQ_H
#define PB_APP_RENDER_SEQ_H

#include <stdint.h>

#include "app/cli.h"
#include "color/color.h"
#include "gpu/gpu.h"
#include "render/frame/sequence.h"

typedef struct pb_seq_opts {
  int32_t first, last;          /* frame numbers, inclusive; t = frame / fps */
  uint32_t warmup;              /* frames first-warmup .. first-1 rendered for the
                                   temporal history, not written */
  double fps;
  const char *png;              /* pattern or NULL */
  uint32_t reference_spp;       /* 0: no per-frame reference and metrics */
  const char *reference_cache;  /* NULL: OUTDIR/reference_cache */
  const char *blender_layer;    /* NULL, or Blender's EXR channel names (render_out.h) */
  const char *blender_passes;   /* NULL (all), or the passes to write */
} pb_seq_opts;

/* Parses "A:B" (or "A" for one frame) into first/last. */
pb_result pb_seq_parse_frames(const char *text, int32_t *first, int32_t *last);

/* Expands the run of '#' in `pattern` to `frame`, zero-padded to the run's
 * length ("out/f_####.exr", 7 -> "out/f_0007.exr"). Errors when the pattern
 * has no '#' (and more than one frame is rendered) or two runs. */
pb_result pb_seq_frame_path(const char *pattern, int32_t frame, char *out, size_t size);

/* Renders and writes the frames; JSON (c->json) and the per-frame reference
 * metrics as the options say. */
pb_result pb_render_sequence(pb_gpu *g, pb_scene *s, pb_gpu_scene *gs, int camera, uint32_t w, uint32_t h,
                             const pb_sequence_desc *sd, const pb_seq_opts *so, const pb_core_opts *c,
                             pb_color *color);

#endif
