/* Skinned and morphed instances (deform.h): the loader's records of them,
 * and their pose: morph, then the skin matrix (or the node's), in double,
 * into pb_scene's float arrays. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/deform.h"

void pb_deform_src_free(pb_deform_src *D) {
  free(D->pos);
  free(D->nrm);
  free(D->tan);
  free(D->dpos);
  free(D->dnrm);
  free(D->dtan);
  free(D->joint);
  free(D->weight);
  memset(D, 0, sizeof *D);
}

pb_result pb_deform_read(const char *path, const pb_gltf_doc *doc, pb_scene *s, const pb_deform *d, int32_t mesh,
                         size_t pi, int32_t skin, const pb_span *pos, const pb_span *nrm, const pb_span *tng,
                         pb_deform_src *D) {
  const pb_gltf_primitive *p = &doc->meshes[mesh].primitives[pi];
  uint64_t n = pos->count;
  memset(D, 0, sizeof *D);
  D->skin = skin;
  D->count = n;
  D->targets = (uint32_t)p->target_count;
  D->pos = malloc((size_t)n * sizeof *D->pos);
  if (nrm) D->nrm = malloc((size_t)n * sizeof *D->nrm);
  if (tng) D->tan = malloc((size_t)n * sizeof *D->tan);
  if (!D->pos || (nrm && !D->nrm) || (tng && !D->tan))
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory for meshes[%d].primitives[%zu]", path, mesh, pi);
  for (uint64_t i = 0; i < n; ++i)
    for (int c = 0; c < 4; ++c) {
      if (c < 3) D->pos[i][c] = pb_span_f(pos, i, c);
      if (c < 3 && nrm) D->nrm[i][c] = pb_span_f(nrm, i, c);
      if (tng) D->tan[i][c] = pb_span_f(tng, i, c);
    }
  pb_result r = PB_OK;
  if (D->targets) r = pb_morph_read_targets(path, doc, mesh, pi, n, nrm != NULL, tng != NULL, &D->dpos, &D->dnrm, &D->dtan);
  if (r == PB_OK && skin >= 0)
    r = pb_skin_read_influences(path, doc, s, mesh, pi, &d->skins[skin], n, &D->influences, &D->joint, &D->weight);
  return r;
}

int pb_deform_src_mirrors(const pb_deform *d, const pb_deform_src *D, int32_t node, const mat4 *node_world) {
  pb_deform_range tmp = {.node = node, .skin = D->skin, .influences = D->influences, .joint = D->joint, .weight = D->weight};
  uint64_t neg = 0;
  for (uint64_t i = 0; i < D->count; ++i) {
    mat4 S;
    pb_skin_matrix(d, &tmp, (uint32_t)i, node_world, &S);
    neg += det3(&S) < 0;
  }
  return 2 * neg > D->count;
}

pb_result pb_deform_add_range(const char *path, pb_deform *d, const pb_deform_src *D, int32_t node,
                              const uint32_t *src_of, uint32_t first, uint32_t nv, uint32_t first_tri,
                              uint32_t tri_count, int flat, pb_deform_range **out) {
  *out = NULL;
  if (!nv) return PB_OK;
  if (d->range_count == d->range_cap) {
    uint32_t c = d->range_cap ? 2 * d->range_cap : 8;
    void *q = realloc(d->ranges, (size_t)c * sizeof *d->ranges);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
    d->ranges = q;
    d->range_cap = c;
  }
  pb_deform_range *R = &d->ranges[d->range_count++];
  memset(R, 0, sizeof *R);
  R->node = node;
  R->skin = D->skin;
  R->first_vertex = first;
  R->vertex_count = nv;
  R->first_tri = first_tri;
  R->tri_count = tri_count;
  R->flat = flat;
  R->target_count = D->targets;
  R->weights = D->targets ? d->node_weights[node] : 0;
  R->influences = D->influences;
  size_t t3 = (size_t)D->targets * nv * 3;
  R->pos = malloc((size_t)nv * sizeof *R->pos);
  if (D->nrm) R->nrm = malloc((size_t)nv * sizeof *R->nrm);
  if (D->tan) R->tan = malloc((size_t)nv * sizeof *R->tan);
  if (D->dpos) R->dpos = malloc(t3 * sizeof *R->dpos);
  if (D->dnrm) R->dnrm = malloc(t3 * sizeof *R->dnrm);
  if (D->dtan) R->dtan = malloc(t3 * sizeof *R->dtan);
  if (D->joint) R->joint = malloc((size_t)nv * D->influences * sizeof *R->joint);
  if (D->weight) R->weight = malloc((size_t)nv * D->influences * sizeof *R->weight);
  if (!R->pos || (D->nrm && !R->nrm) || (D->tan && !R->tan) || (D->dpos && !R->dpos) || (D->dnrm && !R->dnrm) ||
      (D->dtan && !R->dtan) || (D->joint && !R->joint) || (D->weight && !R->weight))
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory for the skin or morph targets of nodes[%d]", path, node);
  for (uint32_t v = 0; v < nv; ++v) {
    uint64_t i = src_of[v];
    memcpy(R->pos[v], D->pos[i], sizeof R->pos[v]);
    if (R->nrm) memcpy(R->nrm[v], D->nrm[i], sizeof R->nrm[v]);
    if (R->tan) memcpy(R->tan[v], D->tan[i], sizeof R->tan[v]);
    for (uint32_t t = 0; t < D->targets; ++t) {
      size_t o = ((size_t)t * nv + v) * 3, q = ((size_t)t * D->count + i) * 3;
      if (R->dpos) memcpy(R->dpos + o, D->dpos + q, 3 * sizeof *R->dpos);
      if (R->dnrm) memcpy(R->dnrm + o, D->dnrm + q, 3 * sizeof *R->dnrm);
      if (R->dtan) memcpy(R->dtan + o, D->dtan + q, 3 * sizeof *R->dtan);
    }
    if (R->joint) memcpy(R->joint + (size_t)v * D->influences, D->joint + i * D->influences, D->influences * sizeof *R->joint);
    if (R->weight)
      memcpy(R->weight + (size_t)v * D->influences, D->weight + i * D->influences, D->influences * sizeof *R->weight);
  }
  if (R->skin >= 0) d->skinned_vertices += nv;
  if (R->target_count) d->morphed_vertices += nv;
  *out = R;
  return PB_OK;
}

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
       * for a node (load_mesh.c). */
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
