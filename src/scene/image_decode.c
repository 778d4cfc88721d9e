#include "scene/image_decode.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

/* stb_image is a third-party single header: compile it here, private to this
 * file, with the warnings it is known for silenced. */
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#define STBI_FAILURE_USERMSG
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wstrict-prototypes"
#include <stb_image.h>

int pb_decode_image_rgba8(const uint8_t *bytes, size_t size, uint32_t max_dim, uint64_t max_pixels,
                          uint8_t **rgba, uint32_t *w, uint32_t *h, const char **why) {
  *rgba = NULL;
  *w = *h = 0;
  *why = "";
  if (size > INT_MAX) {
    *why = "file too large";
    return PB_DECODE_BAD;
  }
  int iw = 0, ih = 0, comp = 0;
  if (!stbi_info_from_memory(bytes, (int)size, &iw, &ih, &comp)) {
    *why = stbi_failure_reason();
    return PB_DECODE_BAD;
  }
  *w = (uint32_t)(iw > 0 ? iw : 0);
  *h = (uint32_t)(ih > 0 ? ih : 0);
  if (iw <= 0 || ih <= 0) {
    *why = "zero image size";
    return PB_DECODE_BAD;
  }
  if (*w > max_dim || *h > max_dim || (uint64_t)*w * *h > max_pixels) return PB_DECODE_TOO_LARGE;
  uint8_t *px = stbi_load_from_memory(bytes, (int)size, &iw, &ih, &comp, 4);
  if (!px) {
    *why = stbi_failure_reason();
    return PB_DECODE_BAD;
  }
  /* Hand back plain malloc'd memory (stb may use its own allocator). */
  size_t n = (size_t)iw * (size_t)ih * 4;
  uint8_t *out = malloc(n);
  if (out) memcpy(out, px, n);
  stbi_image_free(px);
  if (!out) {
    *why = "out of memory";
    return PB_DECODE_BAD;
  }
  *rgba = out;
  return PB_DECODE_OK;
}
