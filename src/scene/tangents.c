/* Tangent generation; see tangents.h. */
#include "scene/tangents.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void pb_basis_any(const float n[3], float t[3], float b[3]) {
  float s = copysignf(1.0f, n[2]);
  float a = -1.0f / (s + n[2]);
  float c = n[0] * n[1] * a;
  t[0] = 1.0f + s * n[0] * n[0] * a;
  t[1] = s * c;
  t[2] = -s * n[0];
  b[0] = c;
  b[1] = s + n[1] * n[1] * a;
  b[2] = -n[1];
}

void pb_tangent_any(const float n[3], float t[3]) {
  float b[3];
  pb_basis_any(n, t, b);
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* t -= n (n . t), normalised; 0 when nothing is left. */
static int orthonormalise(const double n[3], double t[3]) {
  double d = dot3(n, t);
  for (int k = 0; k < 3; ++k) t[k] -= n[k] * d;
  double l = sqrt(dot3(t, t));
  if (!(l > 1e-20) || !isfinite(l)) return 0;
  for (int k = 0; k < 3; ++k) t[k] /= l;
  return 1;
}

pb_result pb_tangents_generate(const float (*positions)[3], const float (*normals)[3],
                               const float (*uvs)[2], uint32_t vertex_count,
                               const uint32_t (*triangles)[3], uint32_t triangle_count,
                               const uint8_t *given, float (*tangents)[4]) {
  if (vertex_count == 0) return PB_OK;
  /* [v][0..2]: sum of dP/du, [v][3..5]: sum of dP/dv. */
  double (*acc)[6] = calloc(vertex_count, sizeof *acc);
  if (!acc) return pb_fail(PB_ERR_NOMEM, "out of memory for the tangents of %u vertices", vertex_count);
  for (uint32_t t = 0; uvs && t < triangle_count; ++t) {
    const uint32_t *v = triangles[t];
    if (v[0] >= vertex_count || v[1] >= vertex_count || v[2] >= vertex_count) continue;
    double e1[3], e2[3];
    for (int k = 0; k < 3; ++k) {
      e1[k] = (double)positions[v[1]][k] - positions[v[0]][k];
      e2[k] = (double)positions[v[2]][k] - positions[v[0]][k];
    }
    double du1 = (double)uvs[v[1]][0] - uvs[v[0]][0], dv1 = (double)uvs[v[1]][1] - uvs[v[0]][1];
    double du2 = (double)uvs[v[2]][0] - uvs[v[0]][0], dv2 = (double)uvs[v[2]][1] - uvs[v[0]][1];
    double r = du1 * dv2 - du2 * dv1;
    if (!(fabs(r) > 1e-20) || !isfinite(r)) continue; /* degenerate uv mapping */
    /* [e1 e2] = [dP/du dP/dv] [du1 du2; dv1 dv2] solved for the two columns. */
    double pu[3], pv[3];
    for (int k = 0; k < 3; ++k) {
      pu[k] = (e1[k] * dv2 - e2[k] * dv1) / r;
      pv[k] = (e2[k] * du1 - e1[k] * du2) / r;
    }
    /* Weight by the triangle's area in uv (|r| / 2) so that each triangle's
     * derivative counts by how much of the texture it covers. */
    double w = fabs(r);
    if (!isfinite(dot3(pu, pu)) || !isfinite(dot3(pv, pv))) continue;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) {
        acc[v[c]][k] += pu[k] * w;
        acc[v[c]][3 + k] += pv[k] * w;
      }
  }
  for (uint32_t i = 0; i < vertex_count; ++i) {
    double n[3] = {normals[i][0], normals[i][1], normals[i][2]};
    double nl = sqrt(dot3(n, n));
    if (!(nl > 1e-20) || !isfinite(nl)) {
      tangents[i][0] = 1, tangents[i][1] = 0, tangents[i][2] = 0, tangents[i][3] = 1;
      continue;
    }
    for (int k = 0; k < 3; ++k) n[k] /= nl;
    double t[3], w = 1.0;
    int ok = 0;
    if (given && given[i]) {
      for (int k = 0; k < 3; ++k) t[k] = tangents[i][k];
      w = tangents[i][3] < 0.0f ? -1.0 : 1.0;
      ok = orthonormalise(n, t);
    }
    if (!ok) {
      for (int k = 0; k < 3; ++k) t[k] = acc[i][k];
      ok = orthonormalise(n, t);
      if (ok) {
        /* Handedness against -dP/dv (image up, see tangents.h). */
        double b[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]};
        double up[3] = {-acc[i][3], -acc[i][4], -acc[i][5]};
        w = dot3(b, up) < 0.0 ? -1.0 : 1.0;
      }
    }
    if (!ok) {
      float nf[3] = {(float)n[0], (float)n[1], (float)n[2]}, tf[3];
      pb_tangent_any(nf, tf);
      for (int k = 0; k < 3; ++k) t[k] = tf[k];
      w = 1.0;
    }
    for (int k = 0; k < 3; ++k) tangents[i][k] = (float)t[k];
    tangents[i][3] = (float)w;
  }
  free(acc);
  return PB_OK;
}
