/* Radiance RGBE (.hdr, .pic) decoding, bounds-checked (Greg Ward, "Real
 * Pixels", Graphics Gems II, 1991; the file format of Radiance's color.c and
 * header.c): a text header of lines ended by an empty line ("#?RADIANCE" or
 * "#?RGBE" first, FORMAT=32-bit_rle_rgbe; EXPOSURE and other lines are
 * skipped, as Blender and OpenImageIO do), a resolution line "-Y H +X W"
 * (rows top to bottom) or "+Y H +X W" (bottom to top), then H scanlines of W
 * RGBE pixels, each flat, old-style run-length encoded (1 1 1 n: repeat the
 * last pixel n << shift times), or new-style (2 2 hi lo: four channel runs of
 * W bytes, a count byte > 128 giving a run of count - 128 copies, otherwise
 * count literal bytes) for 8 <= W < 32768. Every count is checked against the
 * line and every read against the end of the data: malformed input is an
 * error, never a read out of bounds. */
#ifndef PB_IMAGE_HDR_H
#define PB_IMAGE_HDR_H

#include <stddef.h>
#include <stdint.h>

#include "core/result.h"

/* On success *rgb is malloc'd (free()): w x h x 3 floats, top row first,
 * linear (RGBE: mantissa (m + 0.5) 2^(e - 136), 0 for e == 0, as Radiance's
 * colr_color). Errors: PB_ERR_IMAGE (malformed, truncated or an unsupported
 * header: XYZE, rotated orientations, zero size) with a reason in
 * why[0..why_size), PB_ERR_LIMIT (over max_dim per side or max_pixels; the
 * size is read before any pixel memory is allocated), PB_ERR_NOMEM. */
pb_result pb_hdr_decode(const uint8_t *bytes, size_t size, uint32_t max_dim, uint64_t max_pixels, float **rgb,
                        uint32_t *w, uint32_t *h, char *why, size_t why_size);

#endif
