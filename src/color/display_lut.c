/* The baked view's evaluation on the host (color.h pb_color_lut): the
 * shaper and the tetrahedral interpolation, operation for operation as
 * shaders/frame/present.comp does them, so that tests can check the bake without
 * a device and the pass against this. */
#include <math.h>
#include <stdlib.h>

#include "color/color.h"

uint8_t pb_color_to_u8(float x) {
  if (!(x > 0.0f)) return 0;
  if (x >= 1.0f) return 255;
  return (uint8_t)(x * 255.0f + 0.5f);
}

/* Node coordinate of a scene-linear value: 0 at x <= 0 (and NaN), linear up
 * to 1 at 2^lo, then log2-spaced up to size-1 at 2^hi (clamped there). */
static float shape(const pb_color_lut *l, float x) {
  const float x0 = exp2f(l->lo), top = (float)(l->size - 1);
  if (!(x > 0.0f)) return 0.0f;
  if (x < x0) return x / x0;
  float u = 1.0f + (float)(l->size - 2) * ((log2f(x) - l->lo) / (l->hi - l->lo));
  return u < top ? u : top; /* +inf: the top node */
}

static const float *node(const pb_color_lut *l, uint32_t r, uint32_t g, uint32_t b) {
  return l->rgba + 4 * (((size_t)b * l->size + g) * l->size + r);
}

void pb_color_lut_eval(const pb_color_lut *l, float scale, const float rgb[3], float out[3]) {
  uint32_t i[3];
  float f[3];
  for (int k = 0; k < 3; ++k) {
    float u = shape(l, rgb[k] * scale);
    uint32_t n = (uint32_t)u;
    if (n > l->size - 2) n = l->size - 2;
    i[k] = n, f[k] = u - (float)n;
  }
  const float fr = f[0], fg = f[1], fb = f[2];
  const uint32_t r = i[0], g = i[1], b = i[2];
  /* Tetrahedral interpolation (OCIO's Lut3D tetrahedral: the cube split into
   * six tetrahedra along its main diagonal, chosen by the order of the
   * fractions). */
  const float *c000 = node(l, r, g, b), *c111 = node(l, r + 1, g + 1, b + 1);
  const float *ca, *cb;
  float w0, wa, wb, w1;
  if (fr > fg) {
    if (fg > fb) ca = node(l, r + 1, g, b), cb = node(l, r + 1, g + 1, b), w0 = 1 - fr, wa = fr - fg, wb = fg - fb, w1 = fb;
    else if (fr > fb) ca = node(l, r + 1, g, b), cb = node(l, r + 1, g, b + 1), w0 = 1 - fr, wa = fr - fb, wb = fb - fg, w1 = fg;
    else ca = node(l, r, g, b + 1), cb = node(l, r + 1, g, b + 1), w0 = 1 - fb, wa = fb - fr, wb = fr - fg, w1 = fg;
  } else {
    if (fb > fg) ca = node(l, r, g, b + 1), cb = node(l, r, g + 1, b + 1), w0 = 1 - fb, wa = fb - fg, wb = fg - fr, w1 = fr;
    else if (fb > fr) ca = node(l, r, g + 1, b), cb = node(l, r, g + 1, b + 1), w0 = 1 - fg, wa = fg - fb, wb = fb - fr, w1 = fr;
    else ca = node(l, r, g + 1, b), cb = node(l, r + 1, g + 1, b), w0 = 1 - fg, wa = fg - fr, wb = fr - fb, w1 = fb;
  }
  for (int k = 0; k < 3; ++k) {
    float v = w0 * c000[k] + wa * ca[k] + wb * cb[k] + w1 * c111[k];
    out[k] = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
  }
}

void pb_color_lut_destroy(pb_color_lut *lut) {
  if (!lut) return;
  free(lut->rgba);
  lut->rgba = NULL;
  lut->size = 0;
}
