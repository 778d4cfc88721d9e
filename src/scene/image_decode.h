/* PNG/JPEG decoding for textures (stb_image), with the size checked from the
 * header before any pixel memory is allocated. */
#ifndef PB_IMAGE_DECODE_H
#define PB_IMAGE_DECODE_H

#include <stddef.h>
#include <stdint.h>

enum { PB_DECODE_OK = 0, PB_DECODE_BAD = 1, PB_DECODE_TOO_LARGE = 2 };

/* On success *rgba is malloc'd (free()), 4 bytes per pixel, top row first.
 * On PB_DECODE_TOO_LARGE, w and h hold the declared size; on PB_DECODE_BAD
 * *why says what stb_image disliked. */
int pb_decode_image_rgba8(const uint8_t *bytes, size_t size, uint32_t max_dim, uint64_t max_pixels,
                          uint8_t **rgba, uint32_t *w, uint32_t *h, const char **why);

#endif
