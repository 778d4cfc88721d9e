/* glTF animations -> the scene's pb_scene_anim (anim.h), with the nodes
 * they move; the vertex store of animated rigid instances. Part of the
 * loader (load_internal.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/anim.h"
#include "scene/load_internal.h"

/* ---- animations ----------------------------------------------------------
 * glTF animations are checked like every other accessor user, then kept in
 * a pb_scene_anim (anim.h) for pb_scene_set_time. All animations of the file
 * play together on one timeline: Blender exports one action per object as
 * one animation each, and a file's animations are meant to be seen at once
 * (a player that picks one would freeze every other object). Channels apply
 * in file order, so where two animations drive the same node property the
 * later one wins (warned). "weights" channels drive the morph weights of
 * their node's mesh (deform.h). Translation, rotation and scale channels on
 * nodes given by `matrix` (which glTF does not allow to animate) are ignored
 * with a warning. */

static const char *const anim_paths[] = {"translation", "rotation", "scale", "weights"};

/* Morph targets of the mesh nodes[node] draws (every primitive has as many:
 * pb_morph_weights_load). */
static size_t node_targets(const pb_gltf_doc *d, int32_t node) {
  int32_t m = d->nodes[node].mesh;
  if (m < 0 || (size_t)m >= d->mesh_count || !d->meshes[m].primitive_count) return 0;
  return d->meshes[m].primitives[0].target_count;
}

pb_result load_anim_reserve(loader *L, struct pb_scene_anim *a, uint64_t more) {
  uint64_t need = (uint64_t)a->local_count + more;
  if (need <= a->local_cap) return PB_OK;
  if (need > UINT32_MAX / 2) return pb_fail(PB_ERR_LIMIT, "%s: too many animated vertices (%llu)", L->path, (unsigned long long)need);
  uint64_t c = a->local_cap ? a->local_cap : 256;
  while (c < need) c *= 2;
  void *p = realloc(a->local_pos, (size_t)c * sizeof *a->local_pos);
  if (p) a->local_pos = p;
  void *n = p ? realloc(a->local_nrm, (size_t)c * sizeof *a->local_nrm) : NULL;
  if (n) a->local_nrm = n;
  if (!p || !n) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for animated vertices", L->path);
  a->local_cap = (uint32_t)c;
  return PB_OK;
}

pb_result load_anim_push_node(loader *L, int32_t **arr, uint32_t *cap, uint32_t at, int32_t node) {
  if (at >= *cap) {
    uint32_t c = *cap ? *cap : 8;
    while (c <= at) c *= 2;
    int32_t *q = realloc(*arr, (size_t)c * sizeof *q);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    for (uint32_t i = *cap; i < c; ++i) q[i] = -1;
    *arr = q;
    *cap = c;
  }
  (*arr)[at] = node;
  return PB_OK;
}

/* Checks animations[ai].samplers[si]'s interpolation and input (key times:
 * float SCALAR, finite, non-decreasing) and that its output accessor exists. */
static pb_result check_anim_sampler(loader *L, size_t ai, size_t si, int *interp) {
  pb_gltf_doc *d = L->doc;
  const pb_gltf_anim_sampler *g = &d->animations[ai].samplers[si];
  static const int32_t float_only[] = {PB_CT_FLOAT, 0};
  char w[96];
  const char *ip = g->interpolation ? g->interpolation : "LINEAR";
  if (strcmp(ip, "LINEAR") == 0) *interp = PB_ANIM_LINEAR;
  else if (strcmp(ip, "STEP") == 0) *interp = PB_ANIM_STEP;
  else if (strcmp(ip, "CUBICSPLINE") == 0) *interp = PB_ANIM_CUBICSPLINE;
  else
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].samplers[%zu].interpolation: '%s' is not LINEAR, STEP or CUBICSPLINE",
                   L->path, ai, si, ip);
  snprintf(w, sizeof w, "animations[%zu].samplers[%zu].input", ai, si);
  pb_span in;
  pb_result r = pb_accessor_check(L->path, L->doc, g->input, w, 1, float_only, &in);
  if (r != PB_OK) return r;
  /* Keys cost at least 4 bytes of times and 12 of values per key in memory,
   * nothing in the file when the accessors have no bufferView (zeros pass
   * every check below): bounded like vertices (3 x max_triangles) before the
   * per-key loop; convert_anim_sampler bounds the values the same way. */
  if (in.count > 3 * L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: %s: %llu keys is over the limit of %llu", L->path, w, (unsigned long long)in.count,
                   (unsigned long long)(3 * L->desc->max_triangles));
  float prev = 0;
  for (uint64_t k = 0; k < in.count; ++k) {
    float v = pb_span_f(&in, k, 0);
    if (!isfinite(v)) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: time at key %llu is not finite", L->path, w, (unsigned long long)k);
    if (k > 0 && v < prev)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: times decrease at key %llu (%g after %g)", L->path, w, (unsigned long long)k,
                     (double)v, (double)prev);
    prev = v;
  }
  if (*interp == PB_ANIM_CUBICSPLINE && in.count < 2)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: CUBICSPLINE needs at least 2 keys, accessor %d has %llu", L->path, w, g->input,
                   (unsigned long long)in.count);
  if (g->output < 0 || (size_t)g->output >= d->accessor_count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].samplers[%zu].output: accessor %d does not exist (%zu accessors)",
                   L->path, ai, si, g->output, d->accessor_count);
  return PB_OK;
}

/* Reads animations[ai].samplers[si] for a channel of `path` into a new
 * pb_anim_sampler: output shape per path, count = keys (x3 for CUBICSPLINE),
 * every value finite. */
static pb_result convert_anim_sampler(loader *L, struct pb_scene_anim *a, size_t ai, size_t si, int interp, int path,
                                      size_t weights, int *negative_scale) {
  pb_gltf_doc *d = L->doc;
  const pb_gltf_anim_sampler *g = &d->animations[ai].samplers[si];
  static const int32_t float_only[] = {PB_CT_FLOAT, 0};
  static const int32_t norm_types[] = {PB_CT_FLOAT, PB_CT_BYTE, PB_CT_UBYTE, PB_CT_SHORT, PB_CT_USHORT, 0};
  /* Weights: one SCALAR per target per key (glTF 2.0 5.6.2). */
  int comps = path == PB_ANIM_ROTATION ? 4 : path == PB_ANIM_WEIGHTS ? (int)weights : 3;
  char wi[96], wo[128];
  snprintf(wi, sizeof wi, "animations[%zu].samplers[%zu].input", ai, si);
  snprintf(wo, sizeof wo, "animations[%zu].samplers[%zu].output (%s)", ai, si, anim_paths[path]);
  pb_span in, out;
  pb_result r = pb_accessor_check(L->path, L->doc, g->input, wi, 1, float_only, &in);
  int normalizable = path == PB_ANIM_ROTATION || path == PB_ANIM_WEIGHTS;
  if (r == PB_OK)
    r = pb_accessor_check(L->path, L->doc, g->output, wo, path == PB_ANIM_WEIGHTS ? 1 : comps,
                          normalizable ? norm_types : float_only, &out);
  if (r != PB_OK) return r;
  if (out.ct != PB_CT_FLOAT && !out.normalized)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: integer %s keys must be normalized (%s)", L->path, g->output,
                   anim_paths[path], wo);
  uint64_t per = (interp == PB_ANIM_CUBICSPLINE ? 3 : 1) * (path == PB_ANIM_WEIGHTS ? (uint64_t)comps : 1);
  if (out.count != in.count * per)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, %s with %llu keys%s needs %llu", L->path, wo,
                   g->output, (unsigned long long)out.count, interp == PB_ANIM_CUBICSPLINE ? "CUBICSPLINE" : "LINEAR/STEP",
                   (unsigned long long)in.count, path == PB_ANIM_WEIGHTS ? " for its node's morph targets" : "",
                   (unsigned long long)(in.count * per));
  /* Values: at most 4 floats per key of the budget check_anim_sampler gave
   * the keys (weights keys carry one per morph target). */
  uint64_t nvalues = out.count * (uint64_t)(path == PB_ANIM_WEIGHTS ? 1 : comps);
  if (nvalues > 4 * 3 * L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: %s: %llu values is over the limit of %llu", L->path, wo, (unsigned long long)nvalues,
                   (unsigned long long)(4 * 3 * L->desc->max_triangles));
  pb_anim_sampler *S = &a->samplers[a->sampler_count];
  memset(S, 0, sizeof *S);
  S->times = malloc((size_t)in.count * sizeof *S->times);
  S->values = malloc((size_t)nvalues * sizeof *S->values);
  if (!S->times || !S->values) {
    free(S->times);
    free(S->values);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory for %s", L->path, wo);
  }
  a->sampler_count++; /* owned by a from here */
  S->key_count = (uint32_t)in.count;
  S->comps = comps;
  S->interp = interp;
  for (uint64_t k = 0; k < in.count; ++k) S->times[k] = pb_span_f(&in, k, 0);
  /* Weights arrive as scalars, `comps` per key (element): the same layout. */
  int ec = path == PB_ANIM_WEIGHTS ? 1 : comps;
  for (uint64_t k = 0; k < out.count; ++k)
    for (int c = 0; c < ec; ++c) {
      float v = pb_span_f(&out, k, c);
      if (!isfinite(v))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: element %llu is not finite", L->path, wo, (unsigned long long)k);
      if (path == PB_ANIM_SCALE && (per == 1 || k % 3 == 1) && v < 0) *negative_scale = 1;
      S->values[k * (uint64_t)ec + (uint64_t)c] = v;
    }
  return PB_OK;
}

pb_result load_anims(loader *L) {
  pb_gltf_doc *d = L->doc;
  pb_result r = PB_OK;
  if (!d->animation_count || !d->animations) return PB_OK;
  size_t nch = 0;
  for (size_t ai = 0; ai < d->animation_count; ++ai) nch += d->animations[ai].channel_count;
  struct pb_scene_anim *a = calloc(1, sizeof *a);
  if (!a) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  L->anim = a; /* freed by pb_scene_load unless moved to the scene */
  /* Per node and path: which animation and channel drives it (1-based). */
  size_t (*owner)[4][2] = calloc(d->node_count + 1, sizeof *owner);
  a->channels = calloc(nch + 1, sizeof *a->channels);
  a->samplers = calloc(nch + 1, sizeof *a->samplers);
  if (!owner || !a->channels || !a->samplers) {
    free(owner);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  }
  int negative_scale = 0;
  for (size_t ai = 0; ai < d->animation_count && r == PB_OK; ++ai) {
    const pb_gltf_animation *an = &d->animations[ai];
    int *interp = calloc(an->sampler_count + 1, sizeof *interp);
    if (!interp) r = pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    for (size_t si = 0; si < an->sampler_count && r == PB_OK; ++si) r = check_anim_sampler(L, ai, si, &interp[si]);
    for (size_t ci = 0; ci < an->channel_count && r == PB_OK; ++ci) {
      const pb_gltf_anim_channel *ch = &an->channels[ci];
      if (ch->sampler < 0 || (size_t)ch->sampler >= an->sampler_count) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].channels[%zu].sampler: %d does not exist (%zu samplers)", L->path, ai,
                    ci, ch->sampler, an->sampler_count);
        break;
      }
      const char *ps = ch->path ? ch->path : "";
      int path = -1;
      for (int k = 0; k < 4; ++k)
        if (strcmp(ps, anim_paths[k]) == 0) path = k;
      if (path < 0 && strcmp(ps, "pointer") != 0) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].channels[%zu].target.path: '%s' is not translation, rotation, scale or weights",
                    L->path, ai, ci, ps);
        break;
      }
      if (ch->target_node != -1 && (ch->target_node < 0 || (size_t)ch->target_node >= d->node_count)) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].channels[%zu].target.node: %d does not exist (%zu nodes)", L->path, ai,
                    ci, ch->target_node, d->node_count);
        break;
      }
      if (path < 0) {
        r = load_warn(L, "animations[%zu].channels[%zu]: '%s' channel ignored (animation pointers are not animated)", ai, ci, ps);
        continue;
      }
      if (ch->target_node == -1) {
        r = load_warn(L, "animations[%zu].channels[%zu].target: no node; channel ignored", ai, ci);
        continue;
      }
      int32_t node = ch->target_node;
      size_t targets = path == PB_ANIM_WEIGHTS ? node_targets(d, node) : 0;
      if (path == PB_ANIM_WEIGHTS && !targets) {
        r = load_warn(L, "animations[%zu].channels[%zu]: nodes[%d] draws no morph targets; 'weights' channel ignored", ai, ci, node);
        continue;
      }
      if (path != PB_ANIM_WEIGHTS && d->nodes[node].has_matrix) {
        r = load_warn(L, "animations[%zu].channels[%zu]: nodes[%d] is given by a matrix, which glTF does not allow to animate; channel ignored",
                 ai, ci, node);
        continue;
      }
      size_t *own = owner[node][path];
      if (own[0] == ai + 1) {
        r = pb_fail(PB_ERR_SCENE_INVALID, "%s: animations[%zu].channels[%zu].target: nodes[%d].%s is already animated by channels[%zu]",
                    L->path, ai, ci, node, anim_paths[path], own[1] - 1);
        break;
      }
      if (own[0] &&
          (r = load_warn(L, "animations[%zu].channels[%zu]: nodes[%d].%s is also animated by animations[%zu].channels[%zu]; the later one wins",
                    ai, ci, node, anim_paths[path], own[0] - 1, own[1] - 1)) != PB_OK)
        break;
      own[0] = ai + 1;
      own[1] = ci + 1;
      uint32_t sidx = a->sampler_count;
      if ((r = convert_anim_sampler(L, a, ai, (size_t)ch->sampler, interp[ch->sampler], path, targets, &negative_scale)) != PB_OK)
        break;
      a->channels[a->channel_count++] = (pb_anim_channel){.sampler = sidx, .node = node, .path = path};
    }
    free(interp);
  }
  free(owner);
  if (r != PB_OK) return r;
  if (negative_scale &&
      (r = load_warn(L, "animations: negative scale keys; a pose mirrored differently from the rest pose keeps the rest pose's winding")) != PB_OK)
    return r;
  if (a->channel_count == 0) { /* nothing to pose */
    pb_scene_anim_destroy(a);
    L->anim = NULL;
    return PB_OK;
  }
  a->node_count = (uint32_t)d->node_count;
  a->nodes = calloc(d->node_count + 1, sizeof *a->nodes);
  a->order = calloc(d->node_count + 1, sizeof *a->order);
  a->trs = calloc(d->node_count + 1, sizeof *a->trs);
  a->world = calloc(d->node_count + 1, sizeof *a->world);
  int comps = 4;
  for (uint32_t i = 0; i < a->sampler_count; ++i)
    if (a->samplers[i].comps > comps) comps = a->samplers[i].comps;
  a->values = calloc((size_t)comps, sizeof *a->values);
  if (!a->nodes || !a->order || !a->trs || !a->world || !a->values) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  for (size_t i = 0; i < d->node_count; ++i) {
    const pb_gltf_node *n = &d->nodes[i];
    pb_anim_node *o = &a->nodes[i];
    o->parent = L->parent[i];
    o->has_matrix = n->has_matrix;
    o->matrix = load_node_local(n);
    memcpy(o->t, n->translation, sizeof o->t);
    memcpy(o->r, n->rotation, sizeof o->r);
    memcpy(o->s, n->scale, sizeof o->s);
  }
  /* A node with a translation, rotation or scale channel is animated, and
   * so is every descendant: walk up from each node to the first one known
   * (node_state as scratch: 0 unknown, 1 no, 2 yes; the graph is a forest,
   * load_check_nodes). */
  for (uint32_t i = 0; i < a->channel_count; ++i) {
    pb_anim_node *o = &a->nodes[a->channels[i].node];
    if (a->channels[i].path == PB_ANIM_WEIGHTS) o->weights_animated = 1;
    else o->animated = 1;
  }
  uint8_t *st = L->node_state;
  for (size_t i = 0; i < d->node_count; ++i) {
    int32_t p = (int32_t)i;
    while (p >= 0 && !st[p] && !a->nodes[p].animated) p = L->parent[p];
    uint8_t v = p >= 0 && (a->nodes[p].animated || st[p] == 2) ? 2 : 1;
    for (int32_t q = (int32_t)i; q >= 0 && q != p; q = L->parent[q]) st[q] = v;
    if (p >= 0 && !st[p]) st[p] = v;
  }
  for (size_t i = 0; i < d->node_count; ++i) a->nodes[i].animated = st[i] == 2;
  memset(st, 0, d->node_count); /* visit() starts from zero */
  return PB_OK;
}

/* The union of the key times of the samplers in use. */
void load_anim_range(const struct pb_scene_anim *a, double *start, double *end) {
  double lo = INFINITY, hi = -INFINITY;
  for (uint32_t i = 0; i < a->sampler_count; ++i) {
    const pb_anim_sampler *S = &a->samplers[i];
    lo = fmin(lo, S->times[0]);
    hi = fmax(hi, S->times[S->key_count - 1]);
  }
  *start = lo <= hi ? lo : 0;
  *end = lo <= hi ? hi : 0;
}

/* Once every camera (a synthesized one included) and light exists: their
 * nodes for the whole arrays, and their rest frames. */
pb_result load_anim_finish(loader *L, struct pb_scene_anim *a) {
  pb_scene *s = L->s;
  pb_result r = PB_OK;
  if (s->camera_count) r = load_anim_push_node(L, &a->camera_node, &a->camera_cap, s->camera_count - 1,
                                          a->camera_cap >= s->camera_count ? a->camera_node[s->camera_count - 1] : -1);
  if (r == PB_OK && s->light_count)
    r = load_anim_push_node(L, &a->light_node, &a->light_cap, s->light_count - 1,
                       a->light_cap >= s->light_count ? a->light_node[s->light_count - 1] : -1);
  if (r != PB_OK) return r;
  a->camera_frame = calloc(s->camera_count + 1, sizeof *a->camera_frame);
  a->light_dir = calloc(s->light_count + 1, sizeof *a->light_dir);
  if (!a->camera_frame || !a->light_dir) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  for (uint32_t i = 0; i < s->camera_count; ++i) {
    memcpy(a->camera_frame[i], s->cameras[i].forward, 3 * sizeof(float));
    memcpy(a->camera_frame[i] + 3, s->cameras[i].up, 3 * sizeof(float));
    memcpy(a->camera_frame[i] + 6, s->cameras[i].right, 3 * sizeof(float));
  }
  for (uint32_t i = 0; i < s->light_count; ++i) memcpy(a->light_dir[i], s->lights[i].direction, 3 * sizeof(float));
  return PB_OK;
}
