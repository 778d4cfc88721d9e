/* 8-bit PNG previews through stb_image_write (the one translation unit that
 * holds its implementation). */
#include "image/image.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/fs.h"
#include "core/srgb.h"

/* Third-party code: its own warnings are not ours to fix. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#pragma GCC diagnostic pop

/* Round-to-nearest of v in [0,1] scaled to 0..255; NaN gives 0. */
static uint8_t to_byte(float v) {
  if (!(v > 0.0f)) return 0;
  if (v >= 1.0f) return 255;
  return (uint8_t)(v * 255.0f + 0.5f);
}

typedef struct png_sink {
  FILE *f;
  int failed;
} png_sink;

static void png_write_cb(void *ctx, void *data, int size) {
  png_sink *s = ctx;
  if (size > 0 && fwrite(data, 1, (size_t)size, s->f) != (size_t)size)
    s->failed = 1;
}

/* Encodes 8-bit pixels (`channels` bytes a pixel, rows top first) as a PNG
 * at path, atomically. */
static pb_result write_bytes(const char *path, uint32_t width, uint32_t height,
                             uint32_t channels, const uint8_t *bytes) {
  FILE *f = NULL;
  char *tmp = NULL;
  pb_result r = pb_atomic_open(path, &f, &tmp);
  if (r != PB_OK) return r;
  png_sink sink = {f, 0};
  int ok = stbi_write_png_to_func(png_write_cb, &sink, (int)width, (int)height,
                                  (int)channels, bytes,
                                  (int)(width * channels));
  if (!ok || sink.failed) {
    pb_atomic_abort(f, tmp);
    return pb_fail(ok ? PB_ERR_IO : PB_ERR_NOMEM, "%s: %s", path,
                   ok ? "write failed" : "PNG encoding ran out of memory");
  }
  return pb_atomic_commit(path, f, tmp);
}

/* The size checks both writers share. */
static pb_result check_size(const char *path, uint32_t width, uint32_t height) {
  if (width == 0 || height == 0)
    return pb_fail(PB_ERR_IMAGE, "%s: image size %ux%u is empty", path, width,
                   height);
  if (width > PB_IMAGE_MAX_DIM || height > PB_IMAGE_MAX_DIM ||
      (uint64_t)width * height > PB_IMAGE_MAX_PIXELS)
    return pb_fail(PB_ERR_LIMIT,
                   "%s: image size %ux%u exceeds the limit (%u per side, %llu "
                   "pixels)",
                   path, width, height, PB_IMAGE_MAX_DIM,
                   (unsigned long long)PB_IMAGE_MAX_PIXELS);
  return PB_OK;
}

pb_result pb_png_write_rgb8(const char *path, uint32_t width, uint32_t height,
                            const uint8_t *rgb) {
  assert(path);
  pb_result r = check_size(path, width, height);
  if (r != PB_OK) return r;
  if (!rgb) return pb_fail(PB_ERR_IMAGE, "%s: no pixels", path);
  return write_bytes(path, width, height, 3, rgb);
}

pb_result pb_png_write_srgb(const char *path, uint32_t width, uint32_t height,
                            uint32_t channels, const float *pixels,
                            float exposure) {
  assert(path);
  if (width == 0 || height == 0) return check_size(path, width, height);
  if (channels != 3 && channels != 4)
    return pb_fail(PB_ERR_IMAGE, "%s: %u channels (a PNG preview takes 3 or 4)",
                   path, channels);
  if (!pixels) return pb_fail(PB_ERR_IMAGE, "%s: no pixels", path);
  if (!isfinite(exposure))
    return pb_fail(PB_ERR_USAGE, "%s: exposure must be a finite number", path);
  pb_result r = check_size(path, width, height);
  if (r != PB_OK) return r;

  size_t n = (size_t)width * height;
  uint8_t *bytes = malloc(n * channels);
  if (!bytes) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  const float scale = exp2f(exposure);
  for (size_t i = 0; i < n; ++i) {
    const float *p = pixels + i * channels;
    uint8_t *q = bytes + i * channels;
    for (uint32_t c = 0; c < 3; ++c) q[c] = to_byte(pb_linear_to_srgb(p[c] * scale));
    if (channels == 4) q[3] = to_byte(p[3]);
  }

  r = write_bytes(path, width, height, channels, bytes);
  free(bytes);
  return r;
}
