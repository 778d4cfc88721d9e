/* glTF morph targets (glTF 2.0 3.7.2.2): the targets' displacements, the
 * morph weights of every node that draws a morphed mesh, and a morphed
 * vertex (deform.h).
 *
 * Refused with one-line errors naming the JSON path: primitives of one mesh
 * with different numbers of targets; mesh.weights or node.weights whose
 * length is not the target count, or with a non-finite weight; node.weights
 * on a node without a mesh; a target accessor that is not VEC3 float, whose
 * count is not POSITION's, or with a non-finite value. A target's NORMAL is
 * used only where the primitive has NORMAL (without, normals are the posed
 * faces'), its TANGENT only where the primitive's own TANGENT is used (a
 * normal-mapped material). Weights are not clamped: glTF allows any real
 * weight. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/accessor.h"
#include "scene/deform.h"

pb_result pb_morph_weights_load(const char *path, const pb_gltf_doc *doc, pb_deform *d) {
  for (size_t m = 0; m < doc->mesh_count; ++m) {
    const pb_gltf_mesh *g = &doc->meshes[m];
    size_t t = g->primitive_count ? g->primitives[0].target_count : 0;
    for (size_t p = 1; p < g->primitive_count; ++p)
      if (g->primitives[p].target_count != t)
        return pb_fail(PB_ERR_SCENE_INVALID,
                       "%s: meshes[%zu].primitives[%zu].targets: %zu targets, primitives[0] has %zu (every primitive of a mesh needs the same)",
                       path, m, p, g->primitives[p].target_count, t);
    if (g->weight_count && g->weight_count != t)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%zu].weights: %zu weights for %zu morph targets", path, m, g->weight_count, t);
    for (size_t k = 0; k < g->weight_count; ++k)
      if (!isfinite(g->weights[k]) || fabs(g->weights[k]) > 1e30)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%zu].weights[%zu]: %g is not a finite weight", path, m, k, g->weights[k]);
    if (t > UINT16_MAX)
      return pb_fail(PB_ERR_LIMIT, "%s: meshes[%zu].primitives[0].targets: %zu morph targets (at most 65535)", path, m, t);
  }
  uint64_t total = 0;
  for (size_t n = 0; n < doc->node_count; ++n) {
    const pb_gltf_node *g = &doc->nodes[n];
    if (g->weight_count && g->mesh < 0)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].weights: the node has no mesh to morph", path, n);
    if (g->mesh < 0 || (size_t)g->mesh >= doc->mesh_count) continue; /* load_node.c reports a bad mesh index */
    const pb_gltf_mesh *mesh = &doc->meshes[g->mesh];
    size_t t = mesh->primitive_count ? mesh->primitives[0].target_count : 0;
    if (g->weight_count && g->weight_count != t)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].weights: %zu weights for the %zu morph targets of meshes[%d]", path, n,
                     g->weight_count, t, g->mesh);
    for (size_t k = 0; k < g->weight_count; ++k)
      if (!isfinite(g->weights[k]) || fabs(g->weights[k]) > 1e30)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].weights[%zu]: %g is not a finite weight", path, n, k, g->weights[k]);
    total += t;
  }
  if (total > UINT32_MAX / 2) return pb_fail(PB_ERR_LIMIT, "%s: %llu morph weights", path, (unsigned long long)total);
  d->node_count = (uint32_t)doc->node_count;
  d->node_weights = malloc((doc->node_count + 1) * sizeof *d->node_weights);
  d->weights = calloc((size_t)total + 1, sizeof *d->weights);
  if (!d->node_weights || !d->weights) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for morph weights", path);
  uint32_t at = 0;
  for (size_t n = 0; n < doc->node_count; ++n) {
    const pb_gltf_node *g = &doc->nodes[n];
    d->node_weights[n] = UINT32_MAX;
    if (g->mesh < 0 || (size_t)g->mesh >= doc->mesh_count) continue;
    const pb_gltf_mesh *mesh = &doc->meshes[g->mesh];
    size_t t = mesh->primitive_count ? mesh->primitives[0].target_count : 0;
    if (!t) continue;
    d->node_weights[n] = at;
    const double *src = g->weight_count ? g->weights : mesh->weight_count ? mesh->weights : NULL;
    for (size_t k = 0; k < t; ++k) d->weights[at + k] = src ? (float)src[k] : 0.0f;
    at += (uint32_t)t;
  }
  d->weight_count = at;
  return PB_OK;
}

pb_result pb_morph_read_targets(const char *path, const pb_gltf_doc *doc, int32_t mesh, size_t pi, uint64_t count,
                                int want_normal, int want_tangent, float **dpos, float **dnrm, float **dtan) {
  const pb_gltf_primitive *p = &doc->meshes[mesh].primitives[pi];
  static const int32_t float_only[] = {PB_CT_FLOAT, 0};
  static const char *const names[3] = {"POSITION", "NORMAL", "TANGENT"};
  float **out[3] = {dpos, dnrm, dtan};
  int want[3] = {1, want_normal, want_tangent};
  size_t nt = p->target_count;
  pb_result r = PB_OK;
  for (int a = 0; a < 3; ++a) *out[a] = NULL;
  for (int a = 0; a < 3 && r == PB_OK; ++a) {
    for (size_t t = 0; t < nt && r == PB_OK; ++t) {
      const pb_gltf_target *tg = &p->targets[t];
      int32_t acc = a == 0 ? tg->position : a == 1 ? tg->normal : tg->tangent;
      if (acc == -1) continue;
      char w[128];
      snprintf(w, sizeof w, "meshes[%d].primitives[%zu].targets[%zu].%s", mesh, pi, t, names[a]);
      pb_span sp;
      /* Checked even when unused, as every other attribute. */
      if ((r = pb_accessor_check(path, doc, acc, w, 3, float_only, &sp)) != PB_OK) break;
      if (sp.count != count) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, POSITION has %llu", path, w, acc,
                    (unsigned long long)sp.count, (unsigned long long)count);
        break;
      }
      if (!want[a]) continue;
      if (!*out[a] && !(*out[a] = calloc((size_t)nt * (size_t)count * 3 + 1, sizeof(float)))) {
        r = pb_fail(PB_ERR_NOMEM, "%s: out of memory for the morph targets of meshes[%d].primitives[%zu]", path, mesh, pi);
        break;
      }
      float *dst = *out[a] + t * count * 3;
      for (uint64_t v = 0; v < count && r == PB_OK; ++v)
        for (int c = 0; c < 3; ++c) {
          float x = pb_span_f(&sp, v, c);
          if (!isfinite(x)) {
            r = pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: element %llu is not finite (%s)", path, acc,
                        (unsigned long long)v, w);
            break;
          }
          dst[v * 3 + (uint64_t)c] = x;
        }
    }
  }
  if (r != PB_OK)
    for (int a = 0; a < 3; ++a) {
      free(*out[a]);
      *out[a] = NULL;
    }
  return r;
}

void pb_morph_vertex(const pb_deform *d, const pb_deform_range *r, uint32_t i, double pos[3], double nrm[3],
                     double tan[3]) {
  for (int c = 0; c < 3; ++c) {
    pos[c] = r->pos[i][c];
    if (nrm) nrm[c] = r->nrm ? r->nrm[i][c] : 0;
    if (tan) tan[c] = r->tan ? r->tan[i][c] : 0;
  }
  if (!r->target_count) return;
  const float *w = d->weights + r->weights;
  size_t stride = (size_t)r->vertex_count * 3;
  for (uint32_t t = 0; t < r->target_count; ++t) {
    double wt = w[t];
    if (wt == 0) continue;
    size_t o = t * stride + (size_t)i * 3;
    for (int c = 0; c < 3; ++c) {
      if (r->dpos) pos[c] += wt * r->dpos[o + (size_t)c];
      if (nrm && r->dnrm) nrm[c] += wt * r->dnrm[o + (size_t)c];
      if (tan && r->dtan) tan[c] += wt * r->dtan[o + (size_t)c];
    }
  }
}
