/* glTF skins (glTF 2.0 3.7.3): the skins' joints and inverse bind matrices,
 * each skinned primitive's JOINTS_n / WEIGHTS_n, and the skin matrix of a
 * vertex (deform.h).
 *
 * What the loader refuses (one-line errors naming the JSON path) and what it
 * repairs (a warning each, as the primitive loads):
 *   - skins[i].joints naming a node that does not exist, or twice;
 *     inverseBindMatrices not MAT4 float, fewer than the joints, or not
 *     finite: errors;
 *   - JOINTS_n without WEIGHTS_n (or the reverse), or a count other than
 *     POSITION's: errors; a joint index at or past the skin's joint count
 *     with a positive weight: error (an index out of range with weight 0
 *     is what exporters pad with, and is ignored);
 *   - a negative or non-finite weight: error;
 *   - weights whose sum is not 1 (glTF 2.0 3.7.3.3 asks for a sum of 1;
 *     tolerance PB_SKIN_WEIGHT_TOLERANCE): rescaled to sum 1, warned with the
 *     number of vertices and the worst sum;
 *   - weights that are all 0: the vertex follows its mesh node instead of
 *     the skeleton (the skinned node's transform is otherwise ignored), warned;
 *   - a skinned node whose primitive has no JOINTS_0 / WEIGHTS_0: drawn
 *     with its node's transform, warned (load_mesh.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/accessor.h"
#include "scene/deform.h"

/* |sum - 1| above this is reported. Exporters write float weights rounded
 * to float (sum within ~1e-7 per influence) or normalised bytes and shorts
 * whose sum glTF requires to be exactly 255 / 65535; 2e-3 is half a step of
 * an 8-bit weight, so only weights that were not normalised are warned. */
#define PB_SKIN_WEIGHT_TOLERANCE 2e-3

void pb_deform_destroy(pb_deform *d) {
  if (!d) return;
  for (uint32_t i = 0; i < d->skin_count; ++i) {
    free(d->skins[i].joints);
    free(d->skins[i].ibm);
    free(d->skins[i].joint_mat);
  }
  free(d->skins);
  for (uint32_t i = 0; i < d->range_count; ++i) {
    pb_deform_range *r = &d->ranges[i];
    free(r->pos);
    free(r->nrm);
    free(r->tan);
    free(r->dpos);
    free(r->dnrm);
    free(r->dtan);
    free(r->joint);
    free(r->weight);
  }
  free(d->ranges);
  free(d->weights);
  free(d->node_weights);
  memset(d, 0, sizeof *d);
}

pb_result pb_skins_load(const char *path, const pb_gltf_doc *doc, pb_deform *d) {
  if (!doc->skin_count) return PB_OK;
  d->skins = calloc(doc->skin_count, sizeof *d->skins);
  if (!d->skins) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for skins", path);
  static const int32_t float_only[] = {PB_CT_FLOAT, 0};
  uint8_t *seen = calloc(doc->node_count + 1, 1);
  if (!seen) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for skins", path);
  pb_result r = PB_OK;
  for (size_t i = 0; i < doc->skin_count && r == PB_OK; ++i) {
    const pb_gltf_skin *g = &doc->skins[i];
    pb_skin *k = &d->skins[d->skin_count++];
    if (g->joint_count == 0) {
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: skins[%zu].joints: empty (a skin needs at least one joint)", path, i);
      break;
    }
    if (g->joint_count > UINT16_MAX) {
      r = pb_fail(PB_ERR_LIMIT, "%s: skins[%zu].joints: %zu joints, more than JOINTS_n can address (65535)", path, i,
                  g->joint_count);
      break;
    }
    k->joint_count = (uint32_t)g->joint_count;
    k->joints = malloc(g->joint_count * sizeof *k->joints);
    k->ibm = malloc(g->joint_count * sizeof *k->ibm);
    k->joint_mat = malloc(g->joint_count * sizeof *k->joint_mat);
    if (!k->joints || !k->ibm || !k->joint_mat) {
      r = pb_fail(PB_ERR_NOMEM, "%s: out of memory for skins[%zu]", path, i);
      break;
    }
    for (size_t j = 0; j < g->joint_count && r == PB_OK; ++j) {
      int32_t n = g->joints[j];
      if (n < 0 || (size_t)n >= doc->node_count)
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: skins[%zu].joints[%zu]: node %d does not exist (%zu nodes)", path, i, j, n,
                    doc->node_count);
      else if (seen[n])
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: skins[%zu].joints[%zu]: node %d is already a joint of this skin", path, i, j, n);
      else
        seen[n] = 1, k->joints[j] = n;
    }
    for (size_t j = 0; j < g->joint_count && (size_t)g->joints[j] < doc->node_count && g->joints[j] >= 0; ++j)
      seen[g->joints[j]] = 0;
    if (r != PB_OK) break;
    if (g->skeleton != -1 && (g->skeleton < 0 || (size_t)g->skeleton >= doc->node_count)) {
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: skins[%zu].skeleton: node %d does not exist (%zu nodes)", path, i, g->skeleton,
                  doc->node_count);
      break;
    }
    for (size_t j = 0; j < g->joint_count; ++j) {
      memset(&k->ibm[j], 0, sizeof k->ibm[j]);
      k->ibm[j].m[0] = k->ibm[j].m[5] = k->ibm[j].m[10] = k->ibm[j].m[15] = 1;
    }
    if (g->inverse_bind_matrices == -1) continue;
    char w[64];
    snprintf(w, sizeof w, "skins[%zu].inverseBindMatrices", i);
    pb_span sp;
    if ((r = pb_accessor_check(path, doc, g->inverse_bind_matrices, w, 16, float_only, &sp)) != PB_OK) break;
    if (sp.count < g->joint_count) {
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu matrices, the skin has %zu joints", path, w,
                  g->inverse_bind_matrices, (unsigned long long)sp.count, g->joint_count);
      break;
    }
    for (size_t j = 0; j < g->joint_count && r == PB_OK; ++j)
      for (int c = 0; c < 16; ++c) {
        float v = pb_span_f(&sp, j, c);
        if (!isfinite(v)) {
          r = pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: matrix %zu is not finite", path, w, j);
          break;
        }
        k->ibm[j].m[c] = v;
      }
  }
  free(seen);
  return r;
}

pb_result pb_skin_read_influences(const char *path, const pb_gltf_doc *doc, pb_scene *s, int32_t mesh, size_t pi,
                                  const pb_skin *skin, uint64_t count, uint32_t *influences, uint16_t **joint_out,
                                  float **weight_out) {
  const pb_gltf_primitive *p = &doc->meshes[mesh].primitives[pi];
  static const int32_t joint_types[] = {PB_CT_UBYTE, PB_CT_USHORT, 0};
  static const int32_t weight_types[] = {PB_CT_FLOAT, PB_CT_UBYTE, PB_CT_USHORT, 0};
  *influences = 0;
  *joint_out = NULL;
  *weight_out = NULL;
  size_t sets = p->joint_set_count > p->weight_set_count ? p->joint_set_count : p->weight_set_count;
  char w[128];
  for (size_t k = 0; k < sets; ++k) {
    int32_t ja = k < p->joint_set_count ? p->joints[k] : -1, wa = k < p->weight_set_count ? p->weights[k] : -1;
    if ((ja == -1) != (wa == -1))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%d].primitives[%zu].attributes: %s_%zu without %s_%zu", path, mesh, pi,
                     ja == -1 ? "WEIGHTS" : "JOINTS", k, ja == -1 ? "JOINTS" : "WEIGHTS", k);
    if (ja == -1)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%d].primitives[%zu].attributes: JOINTS_%zu is missing below JOINTS_%zu",
                     path, mesh, pi, k, sets - 1);
  }
  if (sets > 1024)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu].attributes: %zu JOINTS/WEIGHTS sets (at most 1024)", path,
                   mesh, pi, sets);
  uint32_t n = (uint32_t)(4 * sets);
  /* count * n * 4 bytes must fit in size_t (a 32-bit host: count is bounded
   * by the file's POSITION bytes, the sets' accessors cost nothing without
   * a bufferView). */
  if (n && count > SIZE_MAX / sizeof(float) / n)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu].attributes: %llu vertices x %u joint influences do not fit in memory",
                   path, mesh, pi, (unsigned long long)count, n);
  uint16_t *joint = malloc((size_t)count * n * sizeof *joint);
  float *weight = malloc((size_t)count * n * sizeof *weight);
  if (!joint || !weight) {
    free(joint);
    free(weight);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory for the joints of meshes[%d].primitives[%zu]", path, mesh, pi);
  }
  pb_result r = PB_OK;
  for (size_t k = 0; k < sets && r == PB_OK; ++k) {
    pb_span js, ws;
    snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.JOINTS_%zu", mesh, pi, k);
    r = pb_accessor_check(path, doc, p->joints[k], w, 4, joint_types, &js);
    if (r == PB_OK && js.normalized)
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: JOINTS_%zu must not be normalized", path, p->joints[k], k);
    if (r == PB_OK && js.count != count)
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, POSITION has %llu", path, w, p->joints[k],
                  (unsigned long long)js.count, (unsigned long long)count);
    if (r != PB_OK) break;
    snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.WEIGHTS_%zu", mesh, pi, k);
    r = pb_accessor_check(path, doc, p->weights[k], w, 4, weight_types, &ws);
    if (r == PB_OK && ws.ct != PB_CT_FLOAT && !ws.normalized)
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: integer WEIGHTS_%zu must be normalized", path, p->weights[k], k);
    if (r == PB_OK && ws.count != count)
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, POSITION has %llu", path, w, p->weights[k],
                  (unsigned long long)ws.count, (unsigned long long)count);
    for (uint64_t v = 0; v < count && r == PB_OK; ++v)
      for (int c = 0; c < 4; ++c) {
        float x = pb_span_f(&ws, v, c);
        uint32_t j = pb_span_u(&js, v, c);
        if (!isfinite(x) || x < 0) {
          r = pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d element %llu has weight %g (weights must be finite and >= 0)",
                      path, w, p->weights[k], (unsigned long long)v, (double)x);
          break;
        }
        if (j >= skin->joint_count) {
          if (x > 0) {
            r = pb_fail(PB_ERR_SCENE_INVALID,
                        "%s: meshes[%d].primitives[%zu].attributes.JOINTS_%zu: accessor %d element %llu names joint %u, the skin has %u",
                        path, mesh, pi, k, p->joints[k], (unsigned long long)v, j, skin->joint_count);
            break;
          }
          j = 0; /* padding with no weight */
        }
        joint[v * n + 4 * k + (uint64_t)c] = (uint16_t)j;
        weight[v * n + 4 * k + (uint64_t)c] = x;
      }
  }
  uint64_t off = 0, zero = 0;
  double worst = 1;
  for (uint64_t v = 0; v < count && r == PB_OK; ++v) {
    double sum = 0;
    for (uint32_t c = 0; c < n; ++c) sum += weight[v * n + c];
    if (!(sum > 0)) {
      zero++;
      continue;
    }
    if (fabs(sum - 1) > PB_SKIN_WEIGHT_TOLERANCE) {
      off++;
      if (fabs(sum - 1) > fabs(worst - 1)) worst = sum;
    }
    for (uint32_t c = 0; c < n; ++c) weight[v * n + c] = (float)(weight[v * n + c] / sum);
  }
  if (r == PB_OK && off &&
      pb_scene_warn(s, "meshes[%d].primitives[%zu]: skin weights of %llu of %llu vertices do not sum to 1 (worst %.6g); rescaled to 1",
                    mesh, pi, (unsigned long long)off, (unsigned long long)count, worst) != PB_OK)
    r = pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  if (r == PB_OK && zero &&
      pb_scene_warn(s, "meshes[%d].primitives[%zu]: %llu of %llu vertices have no skin weight; they follow their mesh node", mesh,
                    pi, (unsigned long long)zero, (unsigned long long)count) != PB_OK)
    r = pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  if (r != PB_OK) {
    free(joint);
    free(weight);
    return r;
  }
  *influences = n;
  *joint_out = joint;
  *weight_out = weight;
  return PB_OK;
}

void pb_skins_update(pb_deform *d, const mat4 *world) {
  for (uint32_t i = 0; i < d->skin_count; ++i) {
    pb_skin *k = &d->skins[i];
    for (uint32_t j = 0; j < k->joint_count; ++j) k->joint_mat[j] = mat_mul(&world[k->joints[j]], &k->ibm[j]);
  }
}

void pb_skin_matrix(const pb_deform *d, const pb_deform_range *r, uint32_t i, const mat4 *node_world, mat4 *out) {
  if (r->skin < 0) {
    *out = *node_world;
    return;
  }
  const pb_skin *k = &d->skins[r->skin];
  const uint16_t *jt = r->joint + (size_t)i * r->influences;
  const float *wt = r->weight + (size_t)i * r->influences;
  memset(out, 0, sizeof *out);
  int any = 0;
  for (uint32_t c = 0; c < r->influences; ++c) {
    double w = wt[c];
    if (!(w > 0)) continue;
    const double *m = k->joint_mat[jt[c]].m;
    for (int e = 0; e < 16; ++e) out->m[e] += w * m[e];
    any = 1;
  }
  if (!any) *out = *node_world;
}
