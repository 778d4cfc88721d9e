/* The frame's own estimate of its noise, for the noise threshold
 * (pb_render_desc.noise_threshold): the render is a mean of independent
 * photon maps, each gathered by its own camera samples, so any split of the
 * maps into two groups gives two independent renders of the image. At each
 * check the maps finished since the last one form a block, added to the
 * group with fewer samples; the groups' means A (na samples) and B (nb)
 * estimate the pooled mean's per-pixel variance as (A - B)^2 / ((1/na +
 * 1/nb)(na + nb)) (metrics.h pb_metrics_noise_from_parts), measured on the
 * display image (the sRGB encoding of the beauty clamped to [0, 1], the
 * Standard view: peak 1). The estimate is the RMS of that noise, so
 * PSNR = -20 log10(estimate). Bias (the footprints' blur) is not seen; the
 * threshold's default leaves room for it (docs/noise-threshold.md). */
#ifndef PB_RENDER_NOISE_H
#define PB_RENDER_NOISE_H

#include <stddef.h>
#include <stdint.h>

#include "core/result.h"

typedef struct pb_noise_tracker {
  uint32_t width, height;   /* the pixels checked (band 0 of the frame) */
  float *prev;              /* RGBA sums of the samples at the last check */
  float *group_a;           /* RGBA sums of the blocks in group A */
  float *a, *b;             /* scratch: the groups' means */
  uint32_t prev_samples;    /* samples per pixel at the last check */
  uint32_t samples_a, samples_b;
  uint32_t blocks, checks;
  double estimate;          /* RMS display noise of the mean; < 0 before
                               both groups have a block */
  double psnr;              /* -20 log10(estimate) (INFINITY for 0) */
} pb_noise_tracker;

/* Zeroes t for width x height pixels; allocates on the first check. */
void pb_noise_tracker_init(pb_noise_tracker *t, uint32_t width, uint32_t height);
void pb_noise_tracker_free(pb_noise_tracker *t);
/* A check: `mean` the RGBA mean beauty of the first `samples` samples per
 * pixel (samples above the last check's). Updates t->estimate once both
 * groups hold a block. */
pb_result pb_noise_tracker_check(pb_noise_tracker *t, const float *mean, uint32_t samples);
/* The iteration count at which to check next, after a check at `done`
 * iterations (planned: the frame's upper bound): where the estimate's
 * 1/sqrt(maps) decay reaches `threshold`, at most twice `done`, at least
 * done + 1. */
uint32_t pb_noise_tracker_next(const pb_noise_tracker *t, double threshold, uint32_t done, uint32_t planned);

#endif
