/* libFuzzer target: the image decoders alone, called through their headers,
 * without the glTF parser in front (thousands of inputs a second instead of
 * hundreds).
 *
 * The input's signature picks the decoder from the two tables below: the
 * texture decoders (image/decode.h: PNG, JPEG; from memory) and the float
 * environment-map readers (image/image.h: EXR; from a path, so the input is
 * written to the target's folder first). A reader of pb_exr_read's shape
 * (path, limits, pb_image) joins `float_readers` with one line: its name,
 * signature, file name and function. An input with no known signature must
 * be refused by the loader's dispatcher (pb_decode_image_rgba8) as unknown.
 *
 * Besides memory errors and undefined behaviour (ASan + UBSan; libspng,
 * libjpeg-turbo and OpenEXRCore are Debian's libraries, not instrumented:
 * coverage feedback comes from our code, memory checks from ASan's
 * interceptors), the target aborts when a decoder breaks its contract:
 *   - texture decoders: OK with pixels within the limits (every byte read),
 *     TOO_LARGE with a declared size that is over them, BAD with a one-line
 *     reason, never pixels on failure;
 *   - float readers: pb_fuzz_check_image_read;
 *   - the float texture decoder (decode.h pb_decode_image_float: 16-bit PNG,
 *     Radiance, EXR from memory), run on every input: the same contract as
 *     the texture decoders, UNKNOWN exactly when pb_decode_is_float_image
 *     says no. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/result.h"
#include "fuzz_util.h"
#include "image/decode.h"
#include "image/image.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef pb_decode_status (*rgba8_decoder)(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                                          pb_decoded *out);
typedef pb_result (*float_reader)(const char *path, const pb_exr_read_limits *lim, pb_image *out);

static const struct {
  const char *name;
  const char *magic;
  size_t magic_len;
  rgba8_decoder decode;
} rgba8_decoders[] = {
    {"png", "\x89PNG\r\n\x1a\n", 8, pb_decode_png_rgba8},
    {"jpeg", "\xFF\xD8\xFF", 3, pb_decode_jpeg_rgba8},
};

static struct {
  const char *name;
  const char *magic;
  size_t magic_len;
  const char *file;
  float_reader read;
  const char *path; /* set by LLVMFuzzerInitialize */
} float_readers[] = {
    {"exr", "\x76\x2f\x31\x01", 4, "in.exr", pb_exr_read, NULL},
};

#define COUNT(a) (sizeof(a) / sizeof *(a))

/* Limits below the loader's defaults keep every input fast (a 512 x 512
 * RGBA image decodes in about a millisecond) and inside libFuzzer's 2 GB
 * allocation limit; the code paths are the same. */
static const pb_decode_limits tex_lim = {.max_dim = 2048, .max_pixels = 1u << 18};
static const pb_exr_read_limits float_lim = {.max_dim = 2048, .max_pixels = 1u << 18, .max_channels = 16};

static volatile unsigned sink;

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  pb_fuzz_init("image");
  for (size_t i = 0; i < COUNT(float_readers); ++i) float_readers[i].path = pb_fuzz_path(float_readers[i].file);
  return 0;
}

static void check_rgba8(const char *name, pb_decode_status st, const pb_decoded *d) {
  if (pb_fuzz_verbose()) fprintf(stderr, "fuzz_image: %s: status %d %ux%u %s\n", name, (int)st, d->width, d->height, d->why);
  switch (st) {
  case PB_DECODE_OK: {
    if (!d->rgba || !d->width || !d->height || d->width > tex_lim.max_dim || d->height > tex_lim.max_dim ||
        (uint64_t)d->width * d->height > tex_lim.max_pixels)
      pb_fuzz_fail("%s: OK with %ux%u, pixels %p", name, d->width, d->height, (void *)d->rgba);
    unsigned acc = 0;
    size_t n = (size_t)d->width * d->height * 4;
    for (size_t i = 0; i < n; ++i) acc += d->rgba[i];
    sink = acc;
    break;
  }
  case PB_DECODE_TOO_LARGE:
    if (d->rgba || !(d->width > tex_lim.max_dim || d->height > tex_lim.max_dim ||
                     (uint64_t)d->width * d->height > tex_lim.max_pixels))
      pb_fuzz_fail("%s: TOO_LARGE with %ux%u", name, d->width, d->height);
    break;
  case PB_DECODE_BAD:
    if (d->rgba || d->width || d->height || !d->why[0] || strchr(d->why, '\n') || strchr(d->why, '\r') ||
        !memchr(d->why, 0, sizeof d->why))
      pb_fuzz_fail("%s: BAD with %ux%u, reason '%.*s'", name, d->width, d->height, (int)sizeof d->why, d->why);
    break;
  case PB_DECODE_NOMEM:
    if (d->rgba) pb_fuzz_fail("%s: NOMEM with pixels", name);
    break;
  default:
    pb_fuzz_fail("%s: status %d", name, (int)st);
  }
}

static void check_float_texture(const uint8_t *data, size_t size) {
  pb_decoded_float d;
  pb_error_clear();
  pb_decode_status st = pb_decode_image_float(data, size, &tex_lim, &d);
  pb_error_clear();
  int mine = pb_decode_is_float_image(data, size);
  if ((st == PB_DECODE_UNKNOWN) == mine) pb_fuzz_fail("float texture: status %d, is_float_image %d", (int)st, mine);
  switch (st) {
  case PB_DECODE_OK:
    if (!d.rgba || !d.width || !d.height || d.width > tex_lim.max_dim || d.height > tex_lim.max_dim ||
        (uint64_t)d.width * d.height > tex_lim.max_pixels)
      pb_fuzz_fail("float texture: OK with %ux%u, pixels %p", d.width, d.height, (void *)d.rgba);
    for (size_t i = 0; i < (size_t)d.width * d.height * 4; ++i) sink += (unsigned)(d.rgba[i] != 0.0f);
    break;
  case PB_DECODE_TOO_LARGE:
    if (d.rgba || (d.width <= tex_lim.max_dim && d.height <= tex_lim.max_dim &&
                   (uint64_t)d.width * d.height <= tex_lim.max_pixels))
      pb_fuzz_fail("float texture: TOO_LARGE with %ux%u", d.width, d.height);
    break;
  case PB_DECODE_BAD:
    if (d.rgba || !d.why[0] || strchr(d.why, '\n')) pb_fuzz_fail("float texture: BAD without a one-line reason");
    break;
  case PB_DECODE_NOMEM:
  case PB_DECODE_UNKNOWN:
    if (d.rgba) pb_fuzz_fail("float texture: status %d with pixels", (int)st);
    break;
  }
  free(d.rgba);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  check_float_texture(data, size);
  for (size_t i = 0; i < COUNT(rgba8_decoders); ++i)
    if (size >= rgba8_decoders[i].magic_len && memcmp(data, rgba8_decoders[i].magic, rgba8_decoders[i].magic_len) == 0) {
      pb_decoded d;
      check_rgba8(rgba8_decoders[i].name, rgba8_decoders[i].decode(data, size, &tex_lim, &d), &d);
      free(d.rgba);
      return 0;
    }
  for (size_t i = 0; i < COUNT(float_readers); ++i)
    if (size >= float_readers[i].magic_len && memcmp(data, float_readers[i].magic, float_readers[i].magic_len) == 0) {
      pb_fuzz_write(float_readers[i].path, data, size);
      pb_image img;
      pb_error_clear();
      pb_result r = float_readers[i].read(float_readers[i].path, &float_lim, &img);
      pb_fuzz_check_image_read(float_readers[i].path, r, &float_lim, &img);
      pb_error_clear();
      unlink(float_readers[i].path);
      return 0;
    }
  pb_decoded d;
  pb_decode_status st = pb_decode_image_rgba8(data, size, &tex_lim, &d);
  if (st != PB_DECODE_UNKNOWN || !pb_fuzz_all_zero(&d, sizeof d))
    pb_fuzz_fail("no known signature, but the dispatcher gave status %d", (int)st);
  return 0;
}
