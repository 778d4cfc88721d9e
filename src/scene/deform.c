/* Posing a skinned or morphed primitive instance (deform.h): morph, then
 * the skin matrix (or the node's), in double, into pb_scene's float arrays. */
#include <math.h>
#include <string.h>

#include "scene/deform.h"

static void face_normal(const float *a, const float *b, const float *c, double fn[3]) {
  double e1[3] = {(double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2]};
  double e2[3] = {(double)c[0] - a[0], (double)c[1] - a[1], (double)c[2] - a[2]};
  fn[0] = e1[1] * e2[2] - e1[2] * e2[1];
  fn[1] = e1[2] * e2[0] - e1[0] * e2[2];
  fn[2] = e1[0] * e2[1] - e1[1] * e2[0];
  if (!normalize3(fn)) fn[0] = 0, fn[1] = 0, fn[2] = 1; /* zero area: any unit normal */
}

pb_result pb_deform_pose(pb_scene *s, const pb_deform *d, const pb_deform_range *r, const mat4 *world,
                         float (*tangents)[4], double t) {
  const mat4 *M = &world[r->node];
  for (uint32_t i = 0; i < r->vertex_count; ++i) {
    double p[3], n[3], tg[3], pw[3], nw[3], tw[3], N[9];
    pb_morph_vertex(d, r, i, p, r->nrm ? n : NULL, r->tan ? tg : NULL);
    mat4 S;
    pb_skin_matrix(d, r, i, M, &S);
    xform_point(&S, p, pw);
    if (!fits_float3(pw)) {
      const char *path = s->path ? s->path : "scene";
      if (isnan(t))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: its %s takes vertices out of float range", path, r->node,
                       r->skin >= 0 ? "skin" : "transform and morph targets");
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations: at t = %g the %s of nodes[%d] moves vertices out of float range",
                     path, t, r->skin >= 0 ? "skin" : "morph targets", r->node);
    }
    float *P = s->positions[r->first_vertex + i];
    for (int c = 0; c < 3; ++c) P[c] = (float)pw[c];
    if (r->nrm) {
      normal_matrix(&S, N);
      for (int k = 0; k < 3; ++k) nw[k] = N[k] * n[0] + N[3 + k] * n[1] + N[6 + k] * n[2];
      if (!normalize3(nw)) nw[0] = nw[1] = nw[2] = 0; /* fixed below from the face */
      for (int c = 0; c < 3; ++c) s->normals[r->first_vertex + i][c] = (float)nw[c];
    }
    if (r->tan && tangents) {
      float *T = tangents[r->first_vertex + i];
      xform_dir(&S, tg, tw);
      /* A mirroring skin matrix flips the bitangent, as store_tangent does
       * for a node (load.c). */
      float w = ((r->tan[i][3] < 0.0f) != (det3(&S) < 0)) ? -1.0f : 1.0f;
      if (normalize3(tw)) T[0] = (float)tw[0], T[1] = (float)tw[1], T[2] = (float)tw[2], T[3] = w;
    }
  }
  /* Normals from the posed faces: every corner without NORMAL, and a normal
   * that came out zero (the loader's rule: the face normal of a triangle
   * that uses the vertex). */
  for (uint32_t k = 0; k < r->tri_count; ++k) {
    const uint32_t *tri = s->triangles[r->first_tri + k];
    double fn[3] = {0, 0, 1};
    int have = 0;
    for (int c = 0; c < 3; ++c) {
      float *Nn = s->normals[tri[c]];
      if (!r->flat && (Nn[0] != 0 || Nn[1] != 0 || Nn[2] != 0)) continue;
      if (!have) face_normal(s->positions[tri[0]], s->positions[tri[1]], s->positions[tri[2]], fn), have = 1;
      for (int a = 0; a < 3; ++a) Nn[a] = (float)fn[a];
    }
  }
  return PB_OK;
}
