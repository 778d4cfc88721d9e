/* Heat map PNG output (kept apart from metrics.c so that code using only the
 * numbers does not pull in the image writer). */
#include <stdlib.h>

#include "image/image.h"
#include "metrics/metrics.h"

pb_result pb_metrics_write_heatmap(const char *path, const float *test,
                                   const float *ref, uint32_t w, uint32_t h,
                                   uint32_t ch, pb_heatmap_metric metric,
                                   float scale_max, float *scale_used) {
  float *rgb = malloc((size_t)w * h * 3 * sizeof *rgb);
  if (!rgb) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for the heat map", path);
  pb_result r = pb_metrics_heatmap(test, ref, w, h, ch, metric, scale_max, rgb, scale_used);
  if (r == PB_OK) r = pb_png_write_srgb(path, w, h, 3, rgb, 0.0f);
  free(rgb);
  return r;
}
