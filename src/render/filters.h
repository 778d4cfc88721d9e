/* The post-filters of the indirect light, in the chapter's order (seed 001
 * 24.4): temporal (temporal.h, eq. 12-13) then spatial (atrous.h, eq.
 * 14-19), on a resolved frame's AOVs; the beauty takes the filtered
 * indirect in place of the raw one. Caustics get at most a temporal filter
 * (no blur across them). */
#ifndef PB_RENDER_FILTERS_H
#define PB_RENDER_FILTERS_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/render.h"
#include "render/temporal.h"

typedef struct pb_filter_desc {
  uint32_t atrous_iterations; /* 0: no spatial filter */
  float atrous_gamma;         /* as pb_render_desc.atrous_gamma */
  pb_temporal *temporal;      /* NULL: no temporal filter */
  pb_temporal *temporal_caustic; /* NULL: caustics unfiltered; else their own
                                 temporal filter (history clamped to the
                                 frame's neighbourhood; no spatial filter,
                                 so they stay sharp) */
  const float *motion;        /* motion.h vectors (NULL with still) */
  int still;                  /* camera and scene unchanged since the
                                 previous frame */
  struct pb_atrous_pass *atrous; /* the A-Trous pass of this image size, kept
                                 by the caller (sequences); NULL: made for
                                 the call */
} pb_filter_desc;

/* Filters res->indirect in place and updates res->beauty; adds the
 * passes' times and the temporal statistics to res->stats. A result
 * without an indirect AOV is left alone. */
pb_result pb_filter_indirect(pb_gpu *g, pb_render_result *res, const pb_filter_desc *d);

#endif
