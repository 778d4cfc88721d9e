/* Small vector maths and the random stream of the reference renderer
 * (src/ref only). */
#ifndef PB_REF_VEC_H
#define PB_REF_VEC_H

#include <math.h>
#include <stdint.h>

#include "core/mix.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define PB_PI_F 3.14159265358979323846f
#define PB_INV_PI_F 0.31830988618379067154f
/* Shadow rays to point, spot and directional lights stop this fraction of the
 * distance short of the light (pbrt's ShadowEpsilon), so a light placed
 * exactly on a surface is not hidden by that surface. The GPU's direct.comp
 * uses the same value. */
#define PB_SHADOW_EPSILON 1e-4f

/* ---- vectors ------------------------------------------------------------ */

typedef struct v3 {
  float x, y, z;
} v3;

static inline v3 v3_make(float x, float y, float z) { return (v3){x, y, z}; }
static inline v3 v3_load(const float *p) { return (v3){p[0], p[1], p[2]}; }
static inline v3 v3_add(v3 a, v3 b) { return (v3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline v3 v3_sub(v3 a, v3 b) { return (v3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline v3 v3_mul(v3 a, v3 b) { return (v3){a.x * b.x, a.y * b.y, a.z * b.z}; }
static inline v3 v3_scale(v3 a, float s) { return (v3){a.x * s, a.y * s, a.z * s}; }
static inline v3 v3_madd(v3 a, v3 b, float s) {
  return (v3){a.x + b.x * s, a.y + b.y * s, a.z + b.z * s};
}
static inline float v3_dot(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline v3 v3_cross(v3 a, v3 b) {
  return (v3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline float v3_len(v3 a) { return sqrtf(v3_dot(a, a)); }
static inline v3 v3_norm(v3 a) {
  float l = v3_len(a);
  return l > 0 ? v3_scale(a, 1.0f / l) : a;
}
static inline v3 v3_neg(v3 a) { return (v3){-a.x, -a.y, -a.z}; }
static inline float v3_max(v3 a) { return fmaxf(a.x, fmaxf(a.y, a.z)); }
static inline float v3_lum(v3 a) { return 0.2126f * a.x + 0.7152f * a.y + 0.0722f * a.z; }
static inline int v3_is_zero(v3 a) { return a.x == 0 && a.y == 0 && a.z == 0; }
static inline int v3_finite(v3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static inline float v3_get(v3 a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }

/* Orthonormal basis around unit n (Duff et al. 2017, "Building an
 * orthonormal basis, revisited"). */
static inline void v3_basis(v3 n, v3 *t, v3 *b) {
  float s = copysignf(1.0f, n.z);
  float a = -1.0f / (s + n.z);
  float c = n.x * n.y * a;
  *t = v3_make(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  *b = v3_make(c, s + n.y * n.y * a, -n.y);
}

/* ---- random numbers ----------------------------------------------------- */

/* PCG32 (O'Neill 2014). One stream per (seed, pixel, sample) or (seed, pass,
 * photon path), so the picture does not depend on which thread drew what. */
typedef struct pb_rng {
  uint64_t state, inc;
} pb_rng;

static inline uint32_t pb_rng_u32(pb_rng *r) {
  uint64_t old = r->state;
  r->state = old * 6364136223846793005ull + r->inc;
  uint32_t xs = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  uint32_t rot = (uint32_t)(old >> 59u);
  return (xs >> rot) | (xs << ((-rot) & 31));
}

/* Stream from three keys: a domain tag (camera, photon), a 64-bit index and
 * a 32-bit index, with the user's seed. */
static inline pb_rng pb_rng_make(uint64_t seed, uint32_t tag, uint64_t a, uint64_t b) {
  pb_rng r;
  uint64_t h = pb_mix64(seed ^ pb_mix64(((uint64_t)tag << 32) ^ pb_mix64(a) ^ (b * 0xd1b54a32d192ed03ull)));
  r.inc = (pb_mix64(h ^ 0x5851f42d4c957f2dull) << 1) | 1u;
  r.state = 0; /* pcg32_srandom_r: advance, add the initial state, advance */
  pb_rng_u32(&r);
  r.state += h;
  pb_rng_u32(&r);
  return r;
}

/* Uniform in [0, 1). */
static inline float pb_rng_f(pb_rng *r) {
  return (float)(pb_rng_u32(r) >> 8) * (1.0f / 16777216.0f);
}

enum { PB_RNG_CAMERA = 1, PB_RNG_PHOTON = 2, PB_RNG_PIXEL = 3, PB_RNG_LENS = 4 };

#endif
