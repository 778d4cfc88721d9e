/* PNG previews through the OCIO view: the one function every renderer calls
 * to write a display-referred picture. */
#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "color/color.h"
#include "core/fs.h"
#include "image/image.h"

/* stb_image_write's implementation lives in src/image/png.c; this is only
 * its declarations. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

static uint8_t to_byte(float v) {
  if (!(v > 0.0f)) return 0;
  if (v >= 1.0f) return 255;
  return (uint8_t)(v * 255.0f + 0.5f);
}

typedef struct sink {
  FILE *f;
  int failed;
} sink;

static void write_cb(void *ctx, void *data, int size) {
  sink *s = ctx;
  if (size > 0 && fwrite(data, 1, (size_t)size, s->f) != (size_t)size) s->failed = 1;
}

pb_result pb_png_write_display(const char *path, const pb_color *c, uint32_t width,
                               uint32_t height, uint32_t channels,
                               const float *pixels) {
  assert(path);
  if (!c) return pb_png_write_srgb(path, width, height, channels, pixels, 0.0f);
  if (width == 0 || height == 0)
    return pb_fail(PB_ERR_IMAGE, "%s: image size %ux%u is empty", path, width, height);
  if (channels != 3 && channels != 4)
    return pb_fail(PB_ERR_IMAGE, "%s: %u channels (a PNG preview takes 3 or 4)", path, channels);
  if (!pixels) return pb_fail(PB_ERR_IMAGE, "%s: no pixels", path);
  if (width > PB_IMAGE_MAX_DIM || height > PB_IMAGE_MAX_DIM ||
      (uint64_t)width * height > PB_IMAGE_MAX_PIXELS)
    return pb_fail(PB_ERR_LIMIT, "%s: image size %ux%u exceeds the limit", path, width, height);

  const size_t n = (size_t)width * height * channels;
  float *tmp = malloc(n * sizeof *tmp);
  uint8_t *bytes = malloc(n);
  if (!tmp || !bytes) {
    free(tmp);
    free(bytes);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  }
  memcpy(tmp, pixels, n * sizeof *tmp);
  pb_result r = pb_color_apply_display(c, tmp, width, height, channels);
  if (r == PB_OK)
    for (size_t i = 0; i < n; ++i) bytes[i] = to_byte(tmp[i]);
  free(tmp);
  if (r != PB_OK) {
    free(bytes);
    return r;
  }

  FILE *f = NULL;
  char *tmp_path = NULL;
  r = pb_atomic_open(path, &f, &tmp_path);
  if (r != PB_OK) {
    free(bytes);
    return r;
  }
  sink s = {f, 0};
  int ok = stbi_write_png_to_func(write_cb, &s, (int)width, (int)height, (int)channels, bytes,
                                  (int)(width * channels));
  free(bytes);
  if (!ok || s.failed) {
    pb_atomic_abort(f, tmp_path);
    return pb_fail(ok ? PB_ERR_IO : PB_ERR_NOMEM, "%s: %s", path,
                   ok ? "write failed" : "PNG encoding ran out of memory");
  }
  return pb_atomic_commit(path, f, tmp_path);
}
