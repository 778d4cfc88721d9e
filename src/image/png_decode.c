/* PNG textures through libspng 0.7 (decode.h). */
#include <spng.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/decode.h"

/* Ancillary chunks we never use (iCCP, eXIf, zTXt, ...) are still parsed and
 * cached by libspng: bound them (its defaults are 2^31 - 1 bytes per chunk and
 * no cache limit). Real files carry ICC profiles of 0.5-600 KB. */
#define PNG_CHUNK_LIMIT (16u << 20)
#define PNG_CACHE_LIMIT (64u << 20)

static pb_decode_status bad(pb_decoded *out, const char *what, int err) {
  snprintf(out->why, sizeof out->why, "PNG %s: %s", what, spng_strerror(err));
  return PB_DECODE_BAD;
}

pb_decode_status pb_decode_png_rgba8(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                                     pb_decoded *out) {
  memset(out, 0, sizeof *out);
  pb_decode_status st = PB_DECODE_OK;
  uint8_t *px = NULL;
  spng_ctx *ctx = spng_ctx_new(0);
  if (!ctx) return PB_DECODE_NOMEM;
  int e = spng_set_png_buffer(ctx, bytes, size);
  if (!e) e = spng_set_chunk_limits(ctx, PNG_CHUNK_LIMIT, PNG_CACHE_LIMIT);
  if (e) {
    st = bad(out, "set-up", e);
    goto done;
  }
  /* Reads the signature and IHDR only: nothing is allocated for pixels yet. */
  struct spng_ihdr ihdr;
  e = spng_get_ihdr(ctx, &ihdr);
  if (e) {
    st = bad(out, "header", e);
    goto done;
  }
  out->width = ihdr.width;
  out->height = ihdr.height;
  if (ihdr.width > lim->max_dim || ihdr.height > lim->max_dim ||
      (uint64_t)ihdr.width * ihdr.height > lim->max_pixels) {
    st = PB_DECODE_TOO_LARGE;
    goto done;
  }
  size_t n = 0;
  e = spng_decoded_image_size(ctx, SPNG_FMT_RGBA8, &n);
  if (!e && n != (size_t)ihdr.width * ihdr.height * 4) e = SPNG_EOVERFLOW; /* callers rely on w*h*4 */
  if (e) {
    st = bad(out, "header", e);
    goto done;
  }
  px = malloc(n ? n : 1);
  if (!px) {
    st = PB_DECODE_NOMEM;
    goto done;
  }
  e = spng_decode_image(ctx, px, n, SPNG_FMT_RGBA8, SPNG_DECODE_TRNS);
  if (e) {
    st = bad(out, "data", e);
    goto done;
  }
  out->rgba = px;
  px = NULL;
done:
  free(px);
  spng_ctx_free(ctx);
  if (st != PB_DECODE_OK && st != PB_DECODE_TOO_LARGE) out->width = out->height = 0;
  return st;
}
