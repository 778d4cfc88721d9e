/* The host's decoder of the sorted map's 48-byte record (shared/pb_photon.h,
 * pb_gpu_photon_packed), the arithmetic of shaders/common/photon_pack.glsl's
 * pb_photon_unpack in C (tests read the LBVH's photons back through it). */
#ifndef PB_RENDER_PHOTON_PACK_H
#define PB_RENDER_PHOTON_PACK_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "shared/pb_gpu.h"
#include "scene/tangents.h"
#include "shared/pb_photon.h"

static inline float pb_pack_sign(float v) { return v >= 0.0f ? 1.0f : -1.0f; }

/* GLSL's unpackSnorm2x16: component k from bits 16k..16k+15. */
static inline void pb_unpack_snorm2x16(uint32_t w, float out[2]) {
  for (int k = 0; k < 2; ++k) {
    int16_t q = (int16_t)(uint16_t)(w >> (16 * k));
    float f = (float)q / 32767.0f;
    out[k] = f < -1.0f ? -1.0f : f;
  }
}

static inline void pb_unpack_snorm12x2(uint32_t w, float out[2]) {
  out[0] = (float)((int)(w & 0xfffu) - 2048) * (1.0f / 2047.0f);
  out[1] = (float)((int)((w >> 12) & 0xfffu) - 2048) * (1.0f / 2047.0f);
}

static inline void pb_oct_decode(const float e[2], float n[3]) {
  float v[3] = {e[0], e[1], 1.0f - fabsf(e[0]) - fabsf(e[1])};
  if (v[2] < 0.0f) {
    float x = (1.0f - fabsf(v[1])) * pb_pack_sign(v[0]), y = (1.0f - fabsf(v[0])) * pb_pack_sign(v[1]);
    v[0] = x, v[1] = y;
  }
  float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; ++k) n[k] = v[k] / l;
}

/* The record as pb_gpu_photon (radius: the scale s; path, ray_length 0). */
static inline void pb_photon_unpack_host(const pb_gpu_photon_packed *q, pb_gpu_photon *p) {
  memset(p, 0, sizeof *p);
  memcpy(p->position, q->position, sizeof p->position);
  memcpy(p->power, q->power, sizeof p->power);
  p->normal_extent = q->normal_extent;
  p->radius = q->scale;
  float e[2], t[3], b[3], u[2], v[2];
  pb_unpack_snorm2x16(q->normal_oct, e);
  pb_oct_decode(e, p->normal);
  pb_unpack_snorm12x2(q->wi_flags, e);
  pb_oct_decode(e, p->wi);
  uint32_t fl = q->wi_flags >> 24;
  p->flags = (fl & PB_PHOTON_CAUSTIC) | ((fl >> 1) << PB_PHOTON_BOUNCE_SHIFT);
  pb_basis_any(p->normal, t, b);
  pb_unpack_snorm2x16(q->axis_u2, u);
  pb_unpack_snorm2x16(q->axis_v2, v);
  for (int k = 0; k < 3; ++k) {
    p->axis_u[k] = (u[0] * q->scale) * t[k] + (u[1] * q->scale) * b[k];
    p->axis_v[k] = (v[0] * q->scale) * t[k] + (v[1] * q->scale) * b[k];
  }
}

#endif
