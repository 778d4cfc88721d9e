/* Image output and input: OpenEXR through its C API (OpenEXRCore) and PNG
 * previews through stb_image_write. Scene-linear float data throughout;
 * pixels are row-major, top row first, channels interleaved. */
#ifndef PB_IMAGE_H
#define PB_IMAGE_H

#include <stdint.h>

#include "core/result.h"

/* One layer of an EXR: name "" is the main RGBA (channels R,G,B[,A]); any
 * other name gives channels "name.R", "name.G", "name.B" (3 channels),
 * "name.Y"... as Blender's compositor and common viewers expect:
 *   channels 1 -> "name.V" (or "Z" for the layer named "depth"),
 *   channels 3 -> "name.R/G/B" (normal: "name.X/Y/Z"), 4 -> "name.R/G/B/A". */
typedef struct pb_image_layer {
  const char *name;
  uint32_t channels;      /* 1, 3 or 4 */
  const float *pixels;    /* width*height*channels floats */
  const char *const *channel_names; /* optional override, `channels` entries */
} pb_image_layer;

typedef enum pb_exr_pixel { PB_EXR_FLOAT = 0, PB_EXR_HALF = 1 } pb_exr_pixel;

typedef struct pb_exr_desc {
  uint32_t width, height;
  const pb_image_layer *layers;
  uint32_t layer_count;
  pb_exr_pixel pixel_type;   /* 0 = float */
  /* Extra string attributes recorded in the header ("photonbridge/renderer"
   * = "reference", ...); may be NULL. */
  const char *const *attr_names;
  const char *const *attr_values;
  uint32_t attr_count;
} pb_exr_desc;

/* Writes a ZIP-compressed scanline EXR with linear Rec.709 chromaticities.
 * Written to a temporary and renamed: on failure no file (and no partial
 * file) is left at `path`. */
pb_result pb_exr_write(const char *path, const pb_exr_desc *desc);

/* A loaded image: every channel of the file as float, planar is avoided:
 * interleaved in channel order of `channel_names`. */
typedef struct pb_image {
  uint32_t width, height;
  uint32_t channel_count;
  char (*channel_names)[64];
  float *pixels;            /* width*height*channel_count */
} pb_image;

typedef struct pb_exr_read_limits {
  uint32_t max_dim;         /* 0: 32768 */
  uint64_t max_pixels;      /* 0: 256 Mpixel */
  uint32_t max_channels;    /* 0: 64 */
} pb_exr_read_limits;

pb_result pb_exr_read(const char *path, const pb_exr_read_limits *limits,
                      pb_image *out);
void pb_image_destroy(pb_image *img);
/* Index of a channel by exact name, or -1. */
int pb_image_find_channel(const pb_image *img, const char *name);

/* Writes an 8-bit PNG preview of linear RGB(A) data through the plain sRGB
 * encode (the shared OCIO view replaces it in its own issue), scaled by
 * 2^exposure and clamped. channels 3 or 4. Atomic like pb_exr_write. */
pb_result pb_png_write_srgb(const char *path, uint32_t width, uint32_t height,
                            uint32_t channels, const float *pixels,
                            float exposure);

#endif
