/* Texture decoding from memory: PNG through libspng, JPEG through
 * libjpeg-turbo, both to 8-bit RGBA, top row first. Both libraries are built
 * for untrusted input and fuzzed upstream (OSS-Fuzz); docs/scenes.md, "Texture
 * decoding", has the measurement that chose them over stb_image.
 *
 * Contract of every decoder here: the declared size is read from the header
 * and checked against the limits before any pixel memory is allocated; no
 * input reaches undefined behaviour; nothing is printed. */
#ifndef PB_IMAGE_DECODE_H
#define PB_IMAGE_DECODE_H

#include <stddef.h>
#include <stdint.h>

typedef enum pb_decode_status {
  PB_DECODE_OK = 0,
  PB_DECODE_BAD = 1,       /* malformed or unsupported: `why` says what */
  PB_DECODE_TOO_LARGE = 2, /* width/height hold the declared size */
  PB_DECODE_NOMEM = 3,
  PB_DECODE_UNKNOWN = 4    /* neither PNG nor JPEG (pb_decode_image_rgba8) */
} pb_decode_status;

typedef struct pb_decode_limits {
  uint32_t max_dim;    /* per side */
  uint64_t max_pixels; /* width * height */
} pb_decode_limits;

enum { PB_DECODE_WHY_SIZE = 160 };

typedef struct pb_decoded {
  uint8_t *rgba; /* malloc'd (free()), width * height * 4 bytes; NULL unless OK */
  uint32_t width, height;
  char why[PB_DECODE_WHY_SIZE]; /* one line, set for PB_DECODE_BAD */
} pb_decoded;

/* PNG: every colour type and bit depth, Adam7 interlacing; palette and tRNS
 * transparency become alpha; 16-bit samples keep their high byte; gAMA,
 * cHRM, iCCP and sRGB are ignored (glTF textures are sRGB or linear by their
 * role, not by their file). A bad CRC is an error in the chunks libspng
 * reads whole (IHDR, PLTE, tRNS, ...); libspng 0.7 need not check the last
 * IDAT's once the image data is complete. */
pb_decode_status pb_decode_png_rgba8(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                                     pb_decoded *out);

/* JPEG (baseline, progressive, arithmetic; grey, YCbCr, RGB, CMYK and YCCK):
 * CMYK is converted as Adobe's inverted CMYK when the file has an Adobe
 * marker. Recoverable data errors (a truncated scan) decode with libjpeg's
 * grey fill, as every viewer does; more than 500 progressive scans is an
 * error (the scan-count bound of libjpeg-turbo's TJFLAG_LIMITSCANS). */
pb_decode_status pb_decode_jpeg_rgba8(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                                      pb_decoded *out);

/* PNG or JPEG by the file's signature (PB_DECODE_UNKNOWN for anything else). */
pb_decode_status pb_decode_image_rgba8(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                                       pb_decoded *out);

/* Images with more than 8 bits a channel, as linear-or-encoded floats
 * (glTF's core formats are 8-bit PNG and JPEG; a Blender float image, an
 * HDR emission map or a 16-bit data map keeps its precision this way,
 * scene.h pb_texture.rgbah):
 * - PNG of bit depth 16: every colour type, RGBA16 through libspng, each
 *   sample / 65535 (still encoded: the slot decides sRGB, as for 8 bits);
 * - Radiance RGBE (.hdr: image/hdr.h), alpha 1;
 * - OpenEXR (image.h pb_exr_read_memory): R, G, B (Y for a luminance file)
 *   and A when present (else 1); other channels ignored.
 * The values of HDR and EXR are linear scene values (`linear` 1), never
 * sRGB-decoded. PB_DECODE_UNKNOWN for anything else, including PNGs of at
 * most 8 bits and JPEG (pb_decode_image_rgba8 decodes those). Limits as
 * above, checked before pixel memory is allocated. */
typedef struct pb_decoded_float {
  float *rgba; /* malloc'd (free()), width * height * 4 floats; NULL unless OK */
  uint32_t width, height;
  int linear;  /* 1: scene-linear values (HDR, EXR); 0: encoded samples (PNG) */
  char why[PB_DECODE_WHY_SIZE];
} pb_decoded_float;

/* 1 when the bytes are a 16-bit PNG, an HDR or an EXR file (by signature
 * and, for PNG, IHDR's bit depth): the float decoder's formats. */
int pb_decode_is_float_image(const uint8_t *bytes, size_t size);
pb_decode_status pb_decode_image_float(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                                       pb_decoded_float *out);

#endif
