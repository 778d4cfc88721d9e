/* Texture decoding by signature (decode.h). */
#include <string.h>

#include "image/decode.h"

pb_decode_status pb_decode_image_rgba8(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                                       pb_decoded *out) {
  static const uint8_t png_sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size >= sizeof png_sig && memcmp(bytes, png_sig, sizeof png_sig) == 0)
    return pb_decode_png_rgba8(bytes, size, lim, out);
  /* SOI followed by the first marker's 0xFF. */
  if (size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF)
    return pb_decode_jpeg_rgba8(bytes, size, lim, out);
  memset(out, 0, sizeof *out);
  return PB_DECODE_UNKNOWN;
}
