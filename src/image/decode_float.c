/* Texture images with more than 8 bits a channel (decode.h
 * pb_decode_image_float): 16-bit PNG through libspng, Radiance RGBE through
 * image/hdr.c, OpenEXR through image/exr.c from memory. */
#include <spng.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "core/result.h"
#include "image/decode.h"
#include "image/hdr.h"
#include "image/image.h"

#define PNG_CHUNK_LIMIT (16u << 20) /* as png_decode.c */
#define PNG_CACHE_LIMIT (64u << 20)

static const uint8_t PNG_SIG[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
static const uint8_t EXR_SIG[4] = {0x76, 0x2f, 0x31, 0x01};

static int is_png16(const uint8_t *b, size_t n) {
  /* signature, IHDR length and type, width, height, then the bit depth */
  return n >= 29 && !memcmp(b, PNG_SIG, 8) && !memcmp(b + 12, "IHDR", 4) && b[24] == 16;
}
static int is_exr(const uint8_t *b, size_t n) { return n >= 4 && !memcmp(b, EXR_SIG, 4); }
static int is_hdr(const uint8_t *b, size_t n) {
  return (n >= 10 && !memcmp(b, "#?RADIANCE", 10)) || (n >= 6 && !memcmp(b, "#?RGBE", 6));
}

int pb_decode_is_float_image(const uint8_t *bytes, size_t size) {
  return bytes && (is_png16(bytes, size) || is_exr(bytes, size) || is_hdr(bytes, size));
}

static pb_decode_status too_large(const pb_decode_limits *lim, uint32_t w, uint32_t h) {
  return w > lim->max_dim || h > lim->max_dim || (uint64_t)w * h > lim->max_pixels ? PB_DECODE_TOO_LARGE
                                                                                   : PB_DECODE_OK;
}

static pb_decode_status png16(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                              pb_decoded_float *out) {
  pb_decode_status st = PB_DECODE_OK;
  uint16_t *px = NULL;
  spng_ctx *ctx = spng_ctx_new(0);
  if (!ctx) return PB_DECODE_NOMEM;
  int e = spng_set_png_buffer(ctx, bytes, size);
  if (!e) e = spng_set_chunk_limits(ctx, PNG_CHUNK_LIMIT, PNG_CACHE_LIMIT);
  struct spng_ihdr ihdr;
  if (!e) e = spng_get_ihdr(ctx, &ihdr);
  if (e) {
    snprintf(out->why, sizeof out->why, "PNG header: %s", spng_strerror(e));
    st = PB_DECODE_BAD;
    goto done;
  }
  out->width = ihdr.width, out->height = ihdr.height;
  if ((st = too_large(lim, ihdr.width, ihdr.height)) != PB_DECODE_OK) goto done;
  size_t n = 0;
  e = spng_decoded_image_size(ctx, SPNG_FMT_RGBA16, &n);
  if (!e && n != (size_t)ihdr.width * ihdr.height * 8) e = SPNG_EOVERFLOW;
  if (!e && !(px = malloc(n ? n : 1))) {
    st = PB_DECODE_NOMEM;
    goto done;
  }
  /* SPNG_FMT_RGBA16 is host byte order (libspng's decode docs) */
  if (!e) e = spng_decode_image(ctx, px, n, SPNG_FMT_RGBA16, SPNG_DECODE_TRNS);
  if (e) {
    snprintf(out->why, sizeof out->why, "PNG data: %s", spng_strerror(e));
    st = PB_DECODE_BAD;
    goto done;
  }
  size_t count = (size_t)ihdr.width * ihdr.height * 4;
  out->rgba = malloc(count * sizeof(float));
  if (!out->rgba) {
    st = PB_DECODE_NOMEM;
    goto done;
  }
  for (size_t i = 0; i < count; ++i) out->rgba[i] = (float)px[i] * (1.0f / 65535.0f);
done:
  free(px);
  spng_ctx_free(ctx);
  return st;
}

static pb_decode_status hdr(const uint8_t *bytes, size_t size, const pb_decode_limits *lim, pb_decoded_float *out) {
  float *rgb = NULL;
  uint32_t w = 0, h = 0;
  pb_result r = pb_hdr_decode(bytes, size, lim->max_dim, lim->max_pixels, &rgb, &w, &h, out->why, sizeof out->why);
  out->width = w, out->height = h, out->linear = 1;
  if (r == PB_ERR_LIMIT) return PB_DECODE_TOO_LARGE;
  if (r == PB_ERR_NOMEM) return PB_DECODE_NOMEM;
  if (r != PB_OK) return PB_DECODE_BAD;
  size_t n = (size_t)w * h;
  out->rgba = malloc(n * 4 * sizeof(float));
  if (!out->rgba) {
    free(rgb);
    return PB_DECODE_NOMEM;
  }
  for (size_t i = 0; i < n; ++i) {
    memcpy(out->rgba + 4 * i, rgb + 3 * i, 3 * sizeof(float));
    out->rgba[4 * i + 3] = 1.0f;
  }
  free(rgb);
  return PB_DECODE_OK;
}

static pb_decode_status exr(const uint8_t *bytes, size_t size, const pb_decode_limits *lim, pb_decoded_float *out) {
  pb_exr_read_limits el = {.max_dim = lim->max_dim, .max_pixels = lim->max_pixels, .max_channels = 0};
  pb_image im;
  out->linear = 1;
  pb_result r = pb_exr_read_memory(bytes, size, "EXR", &el, &im);
  if (r != PB_OK) {
    snprintf(out->why, sizeof out->why, "%s", pb_error_message());
    pb_error_clear();
    /* TOO_LARGE is the declared size over the limits (the reader leaves it
     * in im); any other limit (too many channels, a 64-byte channel name) is
     * a file this decoder does not take: BAD with the reader's reason. */
    if (r == PB_ERR_LIMIT && (im.width || im.height)) {
      out->width = im.width, out->height = im.height;
      return PB_DECODE_TOO_LARGE;
    }
    return r == PB_ERR_NOMEM ? PB_DECODE_NOMEM : PB_DECODE_BAD;
  }
  int c[4] = {pb_image_find_channel(&im, "R"), pb_image_find_channel(&im, "G"), pb_image_find_channel(&im, "B"),
              pb_image_find_channel(&im, "A")};
  int y = pb_image_find_channel(&im, "Y");
  if (c[0] < 0 && c[1] < 0 && c[2] < 0) c[0] = c[1] = c[2] = y;
  if (c[0] < 0 || c[1] < 0 || c[2] < 0) {
    snprintf(out->why, sizeof out->why, "EXR without R, G, B (or Y) channels");
    pb_image_destroy(&im);
    return PB_DECODE_BAD;
  }
  size_t n = (size_t)im.width * im.height;
  out->width = im.width, out->height = im.height;
  out->rgba = malloc(n * 4 * sizeof(float));
  if (!out->rgba) {
    pb_image_destroy(&im);
    return PB_DECODE_NOMEM;
  }
  /* EXR rows are top to bottom in the data window, as glTF's images. */
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 4; ++k)
      out->rgba[4 * i + k] = c[k] < 0 ? 1.0f : im.pixels[i * im.channel_count + (size_t)c[k]];
  pb_image_destroy(&im);
  return PB_DECODE_OK;
}

pb_decode_status pb_decode_image_float(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                                       pb_decoded_float *out) {
  memset(out, 0, sizeof *out);
  pb_decode_status st = PB_DECODE_UNKNOWN;
  if (!bytes) return st;
  if (is_png16(bytes, size)) st = png16(bytes, size, lim, out);
  else if (is_exr(bytes, size)) st = exr(bytes, size, lim, out);
  else if (is_hdr(bytes, size)) st = hdr(bytes, size, lim, out);
  if (st != PB_DECODE_OK) {
    free(out->rgba);
    out->rgba = NULL;
    if (st != PB_DECODE_TOO_LARGE) out->width = out->height = 0;
  }
  return st;
}
