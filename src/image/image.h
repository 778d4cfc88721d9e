/* Image output and input: OpenEXR through its C API (OpenEXRCore) and PNG
 * previews through stb_image_write. Scene-linear float data throughout;
 * pixels are row-major, top row first, channels interleaved. */
#ifndef PB_IMAGE_H
#define PB_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "core/result.h"

/* One layer of an EXR. Channel names, unless `channel_names` overrides them:
 *   name "" (or NULL), the main image: 3 -> "R","G","B"; 4 -> "R","G","B","A";
 *     1 -> "Y" (EXR's luminance channel, shown as grey by viewers);
 *   any other name N: 3 -> "N.R","N.G","N.B" (the layer "normal": "normal.X",
 *     "normal.Y","normal.Z"); 4 -> "N.R","N.G","N.B","N.A"; 1 -> "N.V", except
 *     the layer "depth", whose channel is "depth.Z".
 * "depth.Z" is our choice over Blender's "Depth.Z" (its compositor) and the bare
 * "Z" of single-layer files: lower case like every other layer name here, and
 * with a layer prefix so that it never collides with a main-image channel.
 * Callers that want Blender's name pass channel_names = {"Depth.Z"}.
 * A 2-channel layer (or more than 4) needs channel_names. Names are at most 63
 * bytes and unique across the file. */
typedef struct pb_image_layer {
  const char *name;
  uint32_t channels;      /* 1, 3 or 4; any other count needs channel_names */
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
  /* Optional outputs (NULL = not wanted). NaN and +-Inf inputs are written as
   * 0 and counted in *nonfinite_count; with PB_EXR_HALF, finite values beyond
   * the half range are written as +-65504 (not Inf) and counted in
   * *half_clamped_count. Both are set on success and on failure. */
  uint64_t *nonfinite_count;
  uint64_t *half_clamped_count;
} pb_exr_desc;

/* Size limits shared by the writers and the default read limits, so that any
 * file photonbridge writes can be read back with default limits. */
#define PB_IMAGE_MAX_DIM 32768u
#define PB_IMAGE_MAX_PIXELS (256ull * 1024 * 1024)
#define PB_IMAGE_MAX_CHANNELS 64u

/* Writes a single-part, ZIP-compressed scanline EXR (data window = display
 * window = 0,0 .. width-1,height-1; increasing Y) with a chromaticities
 * attribute for linear Rec.709 / sRGB primaries and D65 white. Channels are
 * stored in the sorted order EXR requires, whatever the layer order.
 * Written to a temporary sibling and renamed: on failure no file (and no
 * partial file) is left at `path`, and an existing file there is untouched.
 * Errors: PB_ERR_IO (cannot create or write), PB_ERR_IMAGE (malformed desc:
 * zero size, bad channel count, duplicate or over-long channel names, an
 * attribute name the format reserves), PB_ERR_LIMIT (over PB_IMAGE_MAX_*). */
pb_result pb_exr_write(const char *path, const pb_exr_desc *desc);

/* A loaded image: every channel of the file as float, interleaved in the
 * order of `channel_names`, which is the file's (sorted) channel order. The
 * image is the file's data window; the display window is ignored. */
typedef struct pb_image {
  uint32_t width, height;
  uint32_t channel_count;
  char (*channel_names)[64];
  float *pixels;            /* width*height*channel_count */
  int32_t data_x, data_y;   /* data window origin in the file's pixel space */
} pb_image;

typedef struct pb_exr_read_limits {
  uint32_t max_dim;         /* 0: 32768 */
  uint64_t max_pixels;      /* 0: 256 Mpixel */
  uint32_t max_channels;    /* 0: 64 */
} pb_exr_read_limits;

/* Reads part 0 of a scanline or tiled EXR (level 0 of a mip/rip-mapped one)
 * with half, float or uint channels, all converted to float (uint exactly up
 * to 2^24). Multi-part files: part 0 only, with a warning. Deep data and
 * subsampled channels are refused. `limits` may be NULL (defaults); they are
 * checked before any pixel memory is allocated. Errors: PB_ERR_IO (cannot
 * open, not a regular file), PB_ERR_IMAGE (malformed, truncated or
 * unsupported), PB_ERR_LIMIT, PB_ERR_NOMEM. On failure *out is zeroed, except that a
 * PB_ERR_LIMIT for the image's size leaves the declared width and height
 * (so a texture decoder can say how large; a limit on anything else, such
 * as the channels, leaves them 0). */
pb_result pb_exr_read(const char *path, const pb_exr_read_limits *limits,
                      pb_image *out);
/* The same for an EXR file's bytes in memory (a glTF image in a
 * bufferView or data URI); `name` labels the messages. */
pb_result pb_exr_read_memory(const uint8_t *bytes, size_t size,
                             const char *name,
                             const pb_exr_read_limits *limits, pb_image *out);
void pb_image_destroy(pb_image *img);
/* Index of a channel by exact name, or -1. */
int pb_image_find_channel(const pb_image *img, const char *name);

/* Writes an 8-bit PNG preview of linear RGB(A) data through the plain sRGB
 * encode (the shared OCIO view, src/color, replaces it for the pictures): colour is
 * scaled by 2^exposure, encoded with pb_linear_to_srgb, clamped to [0,1] and
 * rounded to nearest; NaN and negative values give 0. Alpha is written
 * linearly (clamped, rounded, no exposure). channels 3 or 4. Atomic like
 * pb_exr_write. Errors: PB_ERR_IO, PB_ERR_IMAGE (zero size, bad channel
 * count), PB_ERR_USAGE (non-finite exposure), PB_ERR_LIMIT, PB_ERR_NOMEM. */
pb_result pb_png_write_srgb(const char *path, uint32_t width, uint32_t height,
                            uint32_t channels, const float *pixels,
                            float exposure);

/* Writes 8-bit RGB pixels (3 bytes a pixel, rows top first) as they are, no
 * transform: for pictures already in display values, such as a colour-mapped
 * error map. Atomic like pb_png_write_srgb. Errors: PB_ERR_IO, PB_ERR_IMAGE
 * (zero size), PB_ERR_LIMIT, PB_ERR_NOMEM. */
pb_result pb_png_write_rgb8(const char *path, uint32_t width, uint32_t height,
                            const uint8_t *rgb);

#endif
