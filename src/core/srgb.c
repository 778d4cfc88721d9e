/* The sRGB transfer function (IEC 61966-2-1), shared by texture decoding,
 * the PNG writer and the metrics. */
#include <math.h>

#include "core/srgb.h"

float pb_srgb_to_linear(float v) {
  return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

float pb_linear_to_srgb(float v) {
  if (!(v > 0.0f)) return 0.0f; /* also maps NaN to 0 */
  return v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
}
