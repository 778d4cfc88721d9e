/* Double-precision transforms shared by the glTF loader (load.c) and the
 * animation sampler (anim.c), so that a posed scene goes through exactly the
 * arithmetic of the static load. Column-major 4x4 as glTF. Internal. */
#ifndef PB_SCENE_XFORM_H
#define PB_SCENE_XFORM_H

#include <float.h>
#include <math.h>


typedef struct mat4 { double m[16]; } mat4;

static inline mat4 mat_mul(const mat4 *a, const mat4 *b) {
  mat4 r;
  for (int c = 0; c < 4; ++c)
    for (int rr = 0; rr < 4; ++rr) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a->m[k * 4 + rr] * b->m[c * 4 + k];
      r.m[c * 4 + rr] = s;
    }
  return r;
}

/* T * R * S of a glTF node (rotation x y z w, normalised here; a zero
 * quaternion gives a zero rotation block, as before animation existed). */
static inline mat4 trs_matrix(const double translation[3], const double rotation[4], const double scale[3]) {
  mat4 r;
  double x = rotation[0], y = rotation[1], z = rotation[2], w = rotation[3];
  double len = sqrt(x * x + y * y + z * z + w * w);
  if (len > 0) x /= len, y /= len, z /= len, w /= len;
  double R[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                 2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                 2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};
  for (int c = 0; c < 3; ++c) {
    for (int rr = 0; rr < 3; ++rr) r.m[c * 4 + rr] = R[c * 3 + rr] * scale[c];
    r.m[c * 4 + 3] = 0;
  }
  r.m[12] = translation[0];
  r.m[13] = translation[1];
  r.m[14] = translation[2];
  r.m[15] = 1;
  return r;
}

static inline void xform_point(const mat4 *M, const double p[3], double o[3]) {
  for (int r = 0; r < 3; ++r) o[r] = M->m[r] * p[0] + M->m[4 + r] * p[1] + M->m[8 + r] * p[2] + M->m[12 + r];
}
static inline void xform_dir(const mat4 *M, const double v[3], double o[3]) {
  for (int r = 0; r < 3; ++r) o[r] = M->m[r] * v[0] + M->m[4 + r] * v[1] + M->m[8 + r] * v[2];
}
static inline double det3(const mat4 *M) {
  const double *m = M->m;
  return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
         m[8] * (m[1] * m[6] - m[5] * m[2]);
}
/* Inverse-transpose of the upper 3x3 (cofactor matrix / det), for normals. */
static inline void normal_matrix(const mat4 *M, double N[9]) {
  const double *m = M->m;
  double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6], i = m[10];
  double cof[9] = {e * i - f * h, -(d * i - f * g), d * h - e * g,
                   -(b * i - c * h), a * i - c * g, -(a * h - b * g),
                   b * f - c * e, -(a * f - c * d), a * e - b * d};
  /* cof is row-major cofactors; (M^-1)^T = cof / det, stored column-major
   * in N (N[3 c + r], as the callers apply it: n'[r] = sum_c N[3 c + r]
   * n[c]). Until 2026-11-30 N was stored row-major, so callers applied the
   * transpose, M^-1: rotations turned normals the wrong way (a rotation about
   * X or Y flipped them against the face). Sign of det is kept so the normal
   * keeps pointing out of the (possibly mirrored) surface. */
  double det = det3(M);
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) N[3 * col + row] = det != 0 ? cof[3 * row + col] / det : 0;
}
static inline int normalize3(double v[3]) {
  double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(l > 1e-30) || !isfinite(l)) return 0;
  v[0] /= l, v[1] /= l, v[2] /= l;
  return 1;
}
/* A double that becomes a finite float (the scene model stores floats). */
static inline int fits_float(double v) { return fabs(v) <= FLT_MAX; }
static inline int fits_float3(const double v[3]) { return fits_float(v[0]) && fits_float(v[1]) && fits_float(v[2]); }

static inline int finite_mat(const mat4 *M) {
  for (int k = 0; k < 16; ++k)
    if (!isfinite(M->m[k])) return 0;
  return 1;
}

#endif
