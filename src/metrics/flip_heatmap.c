/* FLIP's error map as a PNG (kept apart from flip.c so that code using only
 * the numbers does not pull in the image writer). */
#include <stdlib.h>

#include "image/image.h"
#include "metrics/flip.h"

pb_result pb_flip_write_heatmap(const char *path, const float *error_map, uint32_t w,
                                uint32_t h) {
  uint8_t *rgb = malloc((size_t)w * h * 3);
  if (!rgb) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for the FLIP map", path);
  for (size_t i = 0; i < (size_t)w * h; ++i) pb_flip_magma(error_map[i], rgb + 3 * i);
  pb_result r = pb_png_write_rgb8(path, w, h, rgb);
  free(rgb);
  return r;
}
