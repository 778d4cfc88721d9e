/* glTF mesh primitives -> the scene's vertex and triangle arrays: each
 * primitive instance is checked (its accessors, material and limits) before
 * anything is written, then flattened into world space (or kept for
 * posing: anim.h, deform.h); tangent frames for normal maps at the end.
 * Part of the loader (load_internal.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/anim.h"
#include "scene/blender_material.h"
#include "scene/load_internal.h"
#include "scene/tangents.h"

enum {
  MODE_TRIANGLES = 4,
  MODE_TRIANGLE_STRIP = 5,
  MODE_TRIANGLE_FAN = 6,
};

static const char *const mode_names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP",
                                         "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};

/* Records the file's TANGENT element `src` as vertex `dst` of the scene, in
 * world space: xyz by the node's 3x3 (a direction in the surface, like an
 * edge), w reduced to its sign and flipped by a mirroring transform, since
 * the world normal keeps pointing out while cross(n, t) changes orientation.
 * A non-finite or collapsed tangent is left to pb_tangents_generate. */
static pb_result store_tangent(loader *L, uint32_t dst, const pb_span *tg, uint64_t src, const mat4 *M, int flip) {
  if (dst >= L->tan_cap) {
    uint32_t old = L->tan_cap;
    pb_result r = load_grow(L, (void **)&L->tan, &L->tan_cap, (uint64_t)dst + 1, sizeof *L->tan, "tangents");
    if (r != PB_OK) return r;
    uint8_t *q = realloc(L->tan_given, L->tan_cap);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for tangents", L->path);
    memset(q + old, 0, L->tan_cap - old);
    L->tan_given = q;
  }
  double tl[3] = {pb_span_f(tg, src, 0), pb_span_f(tg, src, 1), pb_span_f(tg, src, 2)}, tw[3];
  float w = pb_span_f(tg, src, 3);
  xform_dir(M, tl, tw);
  if (!isfinite(w) || !normalize3(tw)) return PB_OK;
  for (int k = 0; k < 3; ++k) L->tan[dst][k] = (float)tw[k];
  L->tan[dst][3] = ((w < 0.0f) != (flip != 0)) ? -1.0f : 1.0f;
  L->tan_given[dst] = 1;
  return PB_OK;
}

/* Cycles' default anisotropy tangent for vertex dst (local position pl) of
 * an anisotropic Blender material (pb_blender_radial_tangent), kept like a
 * file TANGENT. */
static pb_result store_radial_tangent(loader *L, uint32_t dst, const double pl[3], const double bmin[3],
                                      const double bmax[3], const double N[9]) {
  if (dst >= L->tan_cap) {
    uint32_t old = L->tan_cap;
    pb_result r = load_grow(L, (void **)&L->tan, &L->tan_cap, (uint64_t)dst + 1, sizeof *L->tan, "tangents");
    if (r != PB_OK) return r;
    uint8_t *q = realloc(L->tan_given, L->tan_cap);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for tangents", L->path);
    memset(q + old, 0, L->tan_cap - old);
    L->tan_given = q;
  }
  if (!pb_blender_radial_tangent(pl, bmin, bmax, N, L->tan[dst])) return PB_OK;
  L->tan[dst][3] = 1.0f;
  L->tan_given[dst] = 1;
  return PB_OK;
}

/* The local bounds of every POSITION of glTF mesh `mesh` (Blender's texture
 * space of the mesh); from the accessors' min/max, the data where those are
 * missing. */
static void mesh_bounds(loader *L, int32_t mesh, double bmin[3], double bmax[3]) {
  const pb_gltf_mesh *me = &L->doc->meshes[mesh];
  for (int k = 0; k < 3; ++k) bmin[k] = INFINITY, bmax[k] = -INFINITY;
  for (size_t pi = 0; pi < me->primitive_count; ++pi) {
    int32_t a = me->primitives[pi].position;
    if (a < 0 || (size_t)a >= L->doc->accessor_count) continue;
    const pb_gltf_accessor *acc = &L->doc->accessors[a];
    if (acc->has_min_max) {
      for (int k = 0; k < 3; ++k) bmin[k] = fmin(bmin[k], acc->min[k]), bmax[k] = fmax(bmax[k], acc->max[k]);
      continue;
    }
    static const int32_t float_only[] = {PB_CT_FLOAT, 0};
    pb_span sp;
    if (pb_accessor_check(L->path, L->doc, a, "POSITION", 3, float_only, &sp) != PB_OK) {
      pb_error_clear(); /* load_primitive reports it */
      continue;
    }
    if (sp.count > 3 * L->desc->max_triangles) continue; /* load_primitive reports it */
    for (uint64_t i = 0; pb_span_has_data(&sp) && i < sp.count; ++i)
      for (int k = 0; k < 3; ++k) {
        double v = pb_span_f(&sp, i, k);
        if (isfinite(v)) bmin[k] = fmin(bmin[k], v), bmax[k] = fmax(bmax[k], v);
      }
  }
  for (int k = 0; k < 3; ++k)
    if (!(bmin[k] <= bmax[k])) bmin[k] = bmax[k] = 0.0;
}


/* A vertex attribute of meshes[mesh].primitives[pi] named `name`:
 * `comps` components of the allowed types (integers normalized), with
 * POSITION's count. */
static pb_result check_attribute(loader *L, int32_t mesh, size_t pi, const char *name, int32_t acc, int comps,
                                 const int32_t *types, uint64_t count, pb_span *out) {
  char w[128];
  snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.%s", mesh, pi, name);
  pb_result r = pb_accessor_check(L->path, L->doc, acc, w, comps, types, out);
  if (r != PB_OK) return r;
  if (out->ct != PB_CT_FLOAT && !out->normalized)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: integer %s must be normalized", L->path, acc, name);
  if (out->count != count)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: accessor %d has %llu elements, POSITION has %llu", L->path, w, acc,
                   (unsigned long long)out->count, (unsigned long long)count);
  return PB_OK;
}

/* What one primitive instance writes per vertex (load_primitive). */
typedef struct prim_src {
  pb_span pos, nrm, uv, uv1, col, tng;
  int has_n, has_uv, has_uv1, has_col, use_t;
  const mat4 *M;        /* vertices are written through it (identity for a
                           deformed instance, which pb_deform_pose poses) */
  double N[9];          /* its normal matrix */
  int flip;
  struct pb_scene_anim *an; /* rigid animation: local vertices kept */
  uint32_t local, base;
  uint32_t *src_of;     /* deformed: scene vertex - base -> source vertex */
  int radial;           /* the material needs Cycles' default anisotropy
                           tangent (pb_blender_needs_tangent) ... */
  double bmin[3], bmax[3]; /* ... over the mesh's local bounds */
} prim_src;

/* Grows a per-vertex array of the scene that exists only once some
 * primitive has the attribute: `*arr` NULL until then; the vertices before
 * it get `fill`. */
static pb_result vertex_attr(loader *L, void **arr, size_t comps, const float *fill, int present) {
  pb_scene *s = L->s;
  if (!*arr && !present) return PB_OK;
  int fresh = !*arr;
  if ((uint64_t)L->vertex_cap > SIZE_MAX / (comps * sizeof(float))) /* a 32-bit host: would wrap (to 0: a free) */
    return pb_fail(PB_ERR_LIMIT, "%s: too many vertices (%u) for this machine's address space", L->path, L->vertex_cap);
  float *q = realloc(*arr, (size_t)(L->vertex_cap ? L->vertex_cap : 1) * comps * sizeof *q); /* 0 bytes would free */
  if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for vertices", L->path);
  *arr = q;
  if (fresh)
    for (uint32_t v = 0; v < s->vertex_count; ++v) memcpy(q + (size_t)v * comps, fill, comps * sizeof *fill);
  return PB_OK;
}

/* Scene vertex `dst` from source element `i`. World position and normal
 * come from the caller (the flat path computes the face normal). */
static pb_result emit_vertex(loader *L, prim_src *P, uint32_t dst, uint64_t i, const double pw[3], const double nw[3],
                             const double pl[3], const double nl[3]) {
  pb_scene *s = L->s;
  static const float white[4] = {1, 1, 1, 1};
  for (int c = 0; c < 3; ++c) s->positions[dst][c] = (float)pw[c], s->normals[dst][c] = (float)nw[c];
  if (P->an)
    for (int c = 0; c < 3; ++c)
      P->an->local_pos[P->local + (dst - P->base)][c] = (float)pl[c], P->an->local_nrm[P->local + (dst - P->base)][c] = (float)nl[c];
  float *U = s->uvs[dst];
  U[0] = P->has_uv ? pb_span_f(&P->uv, i, 0) : 0.0f;
  U[1] = P->has_uv ? pb_span_f(&P->uv, i, 1) : 0.0f;
  if (!isfinite(U[0]) || !isfinite(U[1])) U[0] = U[1] = 0;
  if (s->uvs1) {
    float *U1 = s->uvs1[dst];
    U1[0] = P->has_uv1 ? pb_span_f(&P->uv1, i, 0) : 0.0f;
    U1[1] = P->has_uv1 ? pb_span_f(&P->uv1, i, 1) : 0.0f;
    if (!isfinite(U1[0]) || !isfinite(U1[1])) U1[0] = U1[1] = 0;
  }
  if (s->colors) {
    /* COLOR_0 (glTF 2.0 3.7.2.1): linear RGB or RGBA, alpha 1 for VEC3;
     * clamped to [0, 1] (float colours may stray; a base colour is a
     * reflectance). */
    float *C = s->colors[dst];
    memcpy(C, white, sizeof white);
    if (P->has_col)
      for (int c = 0; c < (P->col.elem / pb_component_size(P->col.ct) == 4 ? 4 : 3); ++c) {
        float x = pb_span_f(&P->col, i, c);
        C[c] = isfinite(x) ? (x < 0 ? 0 : x > 1 ? 1 : x) : 0;
      }
  }
  if (P->src_of) P->src_of[dst - P->base] = (uint32_t)i;
  if (P->use_t && !P->src_of) return store_tangent(L, dst, &P->tng, i, P->M, P->flip);
  if (P->radial && !P->src_of) return store_radial_tangent(L, dst, pl, P->bmin, P->bmax, P->N);
  return PB_OK;
}

/* A deformed instance's range (deform.c keeps it), posed once with the
 * file's transforms and weights; the file's tangents go to the loader's
 * TANGENT table (load_tangents keeps them). */
static pb_result deform_add(loader *L, int32_t node, const pb_deform_src *D, const prim_src *P, uint32_t tri_base) {
  pb_scene *s = L->s;
  pb_deform_range *R = NULL;
  pb_result r = pb_deform_add_range(L->path, &L->deform, D, node, P->src_of, P->base, s->vertex_count - P->base, tri_base,
                                    s->triangle_count - tri_base, !P->has_n, &R);
  if (r != PB_OK || !R) return r;
  if (R->tan) {
    /* The grown bytes are cleared as in store_tangent: load_tangents reads
     * tan_given for every vertex below tan_cap, also the rigid ones before
     * this range (they were left uninitialised, read as "file tangent"). */
    uint32_t old = L->tan_cap;
    if ((r = load_grow(L, (void **)&L->tan, &L->tan_cap, s->vertex_count, sizeof *L->tan, "tangents")) != PB_OK) return r;
    uint8_t *q = realloc(L->tan_given, L->tan_cap ? L->tan_cap : 1); /* 0 bytes would free */
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for tangents", L->path);
    L->tan_given = q;
    memset(q + old, 0, L->tan_cap - old);
    memset(L->tan + P->base, 0, (size_t)R->vertex_count * sizeof *L->tan);
  }
  if ((r = pb_deform_pose(s, &L->deform, R, L->world, L->tan, NAN)) != PB_OK || !R->tan) return r;
  /* pb_deform_pose writes a tangent only where it normalises (w = +-1): a
   * zero or collapsed file TANGENT is left to pb_tangents_generate, as
   * store_tangent leaves a rigid one (marking the whole range kept garbage). */
  for (uint32_t v = 0; v < R->vertex_count; ++v) L->tan_given[P->base + v] = L->tan[P->base + v][3] != 0.0f;
  return PB_OK;
}

/* One primitive instance on its way into the scene (load_primitive): what
 * its checks found, then where it is written. */
typedef struct prim_job {
  const pb_gltf_primitive *p;
  int32_t node, mesh;
  size_t pi;
  const mat4 *M;         /* the node's world transform */
  pb_span idx;           /* indices, when indexed */
  uint64_t count;        /* POSITION elements */
  uint64_t nidx;         /* indices, or count when not indexed */
  uint64_t ntri;         /* triangles the mode makes */
  uint64_t nverts;       /* scene vertices written */
  int indexed, has_t;
  int32_t mat, skin;
  int skinned, deformed;
  uint32_t tri_base;
  uint64_t dropped;      /* degenerate triangles */
} prim_job;

/* The primitive's accessors: POSITION, every other attribute it has (with
 * POSITION's count), its indices. */
static pb_result prim_check_accessors(loader *L, prim_job *J, prim_src *P) {
  pb_gltf_doc *d = L->doc;
  const pb_gltf_primitive *p = J->p;
  int32_t mesh = J->mesh;
  size_t pi = J->pi;
  char w[128];
  pb_result r;
  static const int32_t float_only[] = {PB_CT_FLOAT, 0};
  static const int32_t uv_types[] = {PB_CT_FLOAT, PB_CT_UBYTE, PB_CT_USHORT, 0};
  static const int32_t index_types[] = {PB_CT_UBYTE, PB_CT_USHORT, PB_CT_UINT, 0};
  snprintf(w, sizeof w, "meshes[%d].primitives[%zu].attributes.POSITION", mesh, pi);
  if ((r = pb_accessor_check(L->path, L->doc, p->position, w, 3, float_only, &P->pos)) != PB_OK) return r;
  uint64_t count = J->count = P->pos.count;
  J->indexed = p->indices != -1;
  P->has_n = p->normal != -1, P->has_uv = p->texcoord0 != -1;
  if (P->has_n && (r = check_attribute(L, mesh, pi, "NORMAL", p->normal, 3, float_only, count, &P->nrm)) != PB_OK) return r;
  if (P->has_uv && (r = check_attribute(L, mesh, pi, "TEXCOORD_0", p->texcoord0, 2, uv_types, count, &P->uv)) != PB_OK)
    return r;
  /* TEXCOORD_1: checked whenever present, kept only when a texture reads
   * uv set 1. */
  if (p->texcoord1 != -1) {
    if ((r = check_attribute(L, mesh, pi, "TEXCOORD_1", p->texcoord1, 2, uv_types, count, &P->uv1)) != PB_OK) return r;
    P->has_uv1 = L->need_uv1;
  }
  /* COLOR_0 (glTF 2.0 3.7.2.1): VEC3 or VEC4, float or normalized UBYTE /
   * USHORT. */
  if (p->color0 != -1) {
    int32_t ca = p->color0;
    int comps = ca >= 0 && (size_t)ca < d->accessor_count && d->accessors[ca].components == 3 ? 3 : 4;
    if ((r = check_attribute(L, mesh, pi, "COLOR_0", ca, comps, uv_types, count, &P->col)) != PB_OK) return r;
    P->has_col = 1;
  }
  /* TANGENT (glTF 2.0 3.7.2.1: VEC4 float, w = +-1 the handedness): checked
   * whenever present, read only for a normal-mapped material. */
  J->has_t = p->tangent != -1;
  if (J->has_t && (r = check_attribute(L, mesh, pi, "TANGENT", p->tangent, 4, float_only, count, &P->tng)) != PB_OK)
    return r;
  J->nidx = count;
  if (J->indexed) {
    snprintf(w, sizeof w, "meshes[%d].primitives[%zu].indices", mesh, pi);
    if ((r = pb_accessor_check(L->path, L->doc, p->indices, w, 1, index_types, &J->idx)) != PB_OK) return r;
    J->nidx = J->idx.count;
  }
  return PB_OK;
}

/* The primitive's material (the default one when it names none) and what
 * it asks of the vertices: tangents, uv set 1. */
static pb_result prim_check_material(loader *L, prim_job *J, prim_src *P) {
  pb_gltf_doc *d = L->doc;
  pb_scene *s = L->s;
  const pb_gltf_primitive *p = J->p;
  int32_t mesh = J->mesh;
  size_t pi = J->pi;
  pb_result r;
  int32_t mat;
  if (p->material != -1) {
    if (p->material < 0 || (size_t)p->material >= d->material_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%d].primitives[%zu].material: %d does not exist (%zu materials)",
                     L->path, mesh, pi, p->material, d->material_count);
    mat = p->material;
  } else {
    mat = load_default_material(L);
  }
  J->mat = mat;
  P->use_t = J->has_t && pb_span_has_data(&P->tng) && mat >= 0 && (uint32_t)mat < s->material_count &&
             pb_material_has_normal_map(&s->materials[mat]);
  P->radial = mat >= 0 && (uint32_t)mat < s->material_count && pb_blender_needs_tangent(&s->materials[mat]);
  if (P->radial) mesh_bounds(L, mesh, P->bmin, P->bmax);
  if (p->texcoord1 == -1 && load_reads_uv1(s, &s->materials[mat]) &&
      (r = load_warn(L, "meshes[%d].primitives[%zu]: its material reads TEXCOORD_1, which the primitive lacks: (0, 0) is used",
                     mesh, pi)) != PB_OK)
    return r;
  if (p->variant_mapping_count &&
      (r = load_warn(L, "meshes[%d].primitives[%zu]: KHR_materials_variants: %zu variant mapping(s); the default material is shown",
                     mesh, pi, p->variant_mapping_count)) != PB_OK)
    return r;
  return PB_OK;
}

/* Skin and morph targets, the triangle count and every limit, before any
 * per-element work or allocation. *skip: the primitive makes no triangle
 * (warned). */
static pb_result prim_check_limits(loader *L, prim_job *J, prim_src *P, int *skip) {
  pb_gltf_doc *d = L->doc;
  pb_scene *s = L->s;
  const pb_gltf_primitive *p = J->p;
  int32_t node = J->node, mesh = J->mesh;
  size_t pi = J->pi;
  uint64_t count = J->count, nidx = J->nidx;
  pb_result r;
  /* Skin and morph targets (deform.h). */
  int32_t skin = J->skin = d->nodes[node].skin;
  J->skinned = skin >= 0 && (p->joint_set_count || p->weight_set_count);
  if (skin >= 0 && !J->skinned &&
      (r = load_warn(L, "nodes[%d]: skins[%d], but meshes[%d].primitives[%zu] has no JOINTS_0 / WEIGHTS_0: drawn with the node's transform",
                     node, skin, mesh, pi)) != PB_OK)
    return r;
  J->deformed = J->skinned || p->target_count;

  /* Triangle list from the mode. Limits come before any per-element work:
   * an accessor without a bufferView costs the file nothing per element. */
  uint64_t ntri = J->ntri = p->mode == MODE_TRIANGLES ? nidx / 3 : (nidx >= 3 ? nidx - 2 : 0);
  /* Fewer than 3 indices (or vertices) make no triangle: skipped before any
   * allocation (a primitive of 0 vertices made the vertex arrays realloc to 0
   * bytes, which frees them: fuzz_gltf found the double free that followed). */
  *skip = 1;
  if (ntri == 0)
    return load_warn(L, "meshes[%d].primitives[%zu]: %llu %s make no triangle: primitive skipped", mesh, pi,
                     (unsigned long long)nidx, J->indexed ? "indices" : "vertices");
  *skip = 0;
  if ((uint64_t)s->triangle_count + ntri > L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu]: more than %llu triangles in the scene", L->path, mesh,
                   pi, (unsigned long long)L->desc->max_triangles);
  /* Flat normals (the glTF rule when NORMAL is absent) need 3 vertices per
   * triangle; otherwise the accessor's vertices are shared. */
  uint64_t nverts = J->nverts = P->has_n ? count : ntri * 3;
  if ((uint64_t)s->vertex_count + nverts > 3 * L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu]: %llu vertices is over the limit of %llu in the scene",
                   L->path, mesh, pi, (unsigned long long)nverts, (unsigned long long)(3 * L->desc->max_triangles));

  /* An accessor without a bufferView reads as zeros (glTF 2.0, 3.6.2.3): zero
   * positions or zero indices make every triangle degenerate. Within the
   * limits such a primitive is skipped before any per-element work or
   * allocation. */
  if (!pb_span_has_data(&P->pos) || (J->indexed && !pb_span_has_data(&J->idx))) {
    *skip = 1;
    return load_warn(L, "meshes[%d].primitives[%zu]: %s has no bufferView (all zeros): primitive skipped", mesh, pi,
                     !pb_span_has_data(&P->pos) ? "POSITION" : "indices");
  }

  /* The source elements are bounded like the scene's vertices before the
   * per-element loops: an indexed primitive without NORMAL makes only its
   * indexed corners count above, and a sparse POSITION without a bufferView
   * holds its count in the file at the cost of one element (2^31 of them
   * took a minute of checking). */
  if (count > 3 * L->desc->max_triangles)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu].attributes.POSITION: %llu elements is over the limit of %llu",
                   L->path, mesh, pi, (unsigned long long)count, (unsigned long long)(3 * L->desc->max_triangles));
  /* Vertex positions: all finite, checked once per accessor element. */
  for (uint64_t i = 0; i < count; ++i)
    for (int c = 0; c < 3; ++c)
      if (!isfinite(pb_span_f(&P->pos, i, c)))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: POSITION element %llu is not finite (%g)", L->path,
                       p->position, (unsigned long long)i, (double)pb_span_f(&P->pos, i, c));
  if (p->mode == MODE_TRIANGLES && nidx % 3 &&
      (r = load_warn(L, "meshes[%d].primitives[%zu]: %llu indices is not a multiple of 3; the last %llu ignored", mesh, pi,
                     (unsigned long long)nidx, (unsigned long long)(nidx % 3))) != PB_OK)
    return r;
  /* Morph targets cost 12 bytes per target, vertex and attribute (twice:
   * the source and the range, deform.h), and a target accessor without a
   * bufferView costs the file nothing: target x vertex pairs are bounded
   * like vertices, before any allocation (also keeps every product below
   * in size_t on 32-bit hosts). */
  uint64_t dverts = count > nverts ? count : nverts;
  if (p->target_count && (uint64_t)p->target_count > 3 * L->desc->max_triangles / dverts)
    return pb_fail(PB_ERR_LIMIT, "%s: meshes[%d].primitives[%zu].targets: %zu morph targets x %llu vertices is over the limit of %llu",
                   L->path, mesh, pi, p->target_count, (unsigned long long)dverts,
                   (unsigned long long)(3 * L->desc->max_triangles));
  return PB_OK;
}

/* Room in the scene's vertex and triangle arrays for the primitive. */
static pb_result prim_reserve(loader *L, const prim_job *J, const prim_src *P) {
  pb_scene *s = L->s;
  pb_result r;
  if ((r = load_grow(L, (void **)&s->positions, &L->vertex_cap, (uint64_t)s->vertex_count + J->nverts, sizeof *s->positions,
                     "vertices")) != PB_OK)
    return r;
  uint32_t vcap = L->vertex_cap ? L->vertex_cap : 1; /* never realloc to 0 bytes (that frees) */
  void *q1 = realloc(s->normals, (size_t)vcap * sizeof *s->normals);
  if (q1) s->normals = q1;
  void *q2 = q1 ? realloc(s->uvs, (size_t)vcap * sizeof *s->uvs) : NULL;
  if (q2) s->uvs = q2;
  if (!q1 || !q2) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for vertices", L->path);
  static const float zero2[2] = {0, 0}, white[4] = {1, 1, 1, 1};
  if ((r = vertex_attr(L, (void **)&s->uvs1, 2, zero2, P->has_uv1)) != PB_OK) return r;
  if ((r = vertex_attr(L, (void **)&s->colors, 4, white, P->has_col)) != PB_OK) return r;
  uint32_t tcap = L->triangle_cap;
  if ((r = load_grow(L, (void **)&s->triangles, &L->triangle_cap, (uint64_t)s->triangle_count + J->ntri, sizeof *s->triangles,
                     "triangles")) != PB_OK)
    return r;
  if (L->triangle_cap != tcap) {
    void *q = realloc(s->triangle_material, (size_t)L->triangle_cap * sizeof *s->triangle_material);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory for triangles", L->path);
    s->triangle_material = q;
  }
  return PB_OK;
}

/* How the instance is written: through the node's transform, or in mesh
 * space for a deformed one (posed after); rigid under an animated node, its
 * local vertices kept for posing (anim.h). */
static pb_result prim_begin(loader *L, prim_job *J, prim_src *P, const pb_deform_src *D) {
  static const mat4 identity = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
  pb_scene *s = L->s;
  pb_result r;
  P->M = J->deformed ? &identity : J->M;
  P->an = !J->deformed && L->anim && L->anim->nodes[J->node].animated ? L->anim : NULL;
  if (P->an) {
    if ((r = load_anim_reserve(L, P->an, J->nverts)) != PB_OK) return r;
    P->local = P->an->local_count;
  }
  if (J->deformed && !(P->src_of = malloc((size_t)(J->nverts ? J->nverts : 1) * sizeof *P->src_of)))
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  /* A mirroring transform reverses the winding. */
  P->flip = J->skinned ? pb_deform_src_mirrors(&L->deform, D, J->node, &L->world[J->node]) : det3(J->M) < 0;
  normal_matrix(P->M, P->N);
  P->base = s->vertex_count;
  J->tri_base = s->triangle_count;
  return PB_OK;
}

/* With NORMAL: every source element becomes one shared scene vertex. */
static pb_result prim_emit_vertices(loader *L, const prim_job *J, prim_src *P) {
  pb_scene *s = L->s;
  pb_result r;
  for (uint64_t i = 0; i < J->count; ++i) {
    double pl[3] = {pb_span_f(&P->pos, i, 0), pb_span_f(&P->pos, i, 1), pb_span_f(&P->pos, i, 2)}, pw[3];
    xform_point(P->M, pl, pw);
    if (!fits_float3(pw))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: transform takes accessors[%d] POSITION element %llu out of float range",
                     L->path, J->node, J->p->position, (unsigned long long)i);
    double nl[3] = {pb_span_f(&P->nrm, i, 0), pb_span_f(&P->nrm, i, 1), pb_span_f(&P->nrm, i, 2)}, nw[3];
    for (int rr = 0; rr < 3; ++rr) nw[rr] = P->N[rr] * nl[0] + P->N[3 + rr] * nl[1] + P->N[6 + rr] * nl[2];
    if (!normalize3(nw)) nw[0] = nw[1] = 0, nw[2] = 0; /* fixed below from the face */
    if ((r = emit_vertex(L, P, P->base + (uint32_t)i, i, pw, nw, pl, nl)) != PB_OK) return r;
  }
  s->vertex_count += (uint32_t)J->count;
  return PB_OK;
}

/* Without NORMAL: the triangle's three corners as new vertices with its
 * face normal; out[] their scene indices. */
static pb_result prim_emit_flat(loader *L, const prim_job *J, prim_src *P, const uint32_t v[3], uint32_t out[3]) {
  pb_scene *s = L->s;
  pb_result r;
  double pl[3][3], pw[3][3];
  for (int c = 0; c < 3; ++c) {
    for (int a = 0; a < 3; ++a) pl[c][a] = pb_span_f(&P->pos, v[c], a);
    xform_point(P->M, pl[c], pw[c]);
    if (!fits_float3(pw[c]))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: transform takes accessors[%d] POSITION element %u out of float range",
                     L->path, J->node, J->p->position, v[c]);
  }
  double e1[3] = {pw[1][0] - pw[0][0], pw[1][1] - pw[0][1], pw[1][2] - pw[0][2]};
  double e2[3] = {pw[2][0] - pw[0][0], pw[2][1] - pw[0][1], pw[2][2] - pw[0][2]};
  double fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  if (!normalize3(fn)) fn[0] = 0, fn[1] = 0, fn[2] = 1; /* zero area: any unit normal */
  static const double none[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    uint32_t o = s->vertex_count++;
    if ((r = emit_vertex(L, P, o, v[c], pw[c], fn, pl[c], none)) != PB_OK) return r;
    out[c] = o;
  }
  return PB_OK;
}

/* The mode's triangles: indices checked against POSITION's count,
 * degenerate ones (a repeated index) dropped and counted in J->dropped, the
 * winding reversed under a mirroring transform. */
static pb_result prim_emit_triangles(loader *L, prim_job *J, prim_src *P) {
  pb_scene *s = L->s;
  const pb_gltf_primitive *p = J->p;
  pb_result r;
  for (uint64_t t = 0; t < J->ntri; ++t) {
    uint64_t k[3];
    if (p->mode == MODE_TRIANGLES) k[0] = 3 * t, k[1] = 3 * t + 1, k[2] = 3 * t + 2;
    else if (p->mode == MODE_TRIANGLE_STRIP) k[0] = t + (t & 1), k[1] = t + 1 - (t & 1), k[2] = t + 2;
    else k[0] = t + 1, k[1] = t + 2, k[2] = 0;
    uint32_t v[3];
    for (int c = 0; c < 3; ++c) {
      uint64_t vi = J->indexed ? pb_span_u(&J->idx, k[c], 0) : k[c];
      if (vi >= J->count)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: accessors[%d]: index %llu at element %llu is out of range (%llu vertices)",
                       L->path, p->indices, (unsigned long long)vi, (unsigned long long)k[c], (unsigned long long)J->count);
      v[c] = (uint32_t)vi;
    }
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      J->dropped++;
      continue;
    }
    if (P->flip) {
      uint32_t tmp = v[1];
      v[1] = v[2];
      v[2] = tmp;
    }
    uint32_t out[3];
    if (P->has_n) {
      for (int c = 0; c < 3; ++c) out[c] = P->base + v[c];
    } else if ((r = prim_emit_flat(L, J, P, v, out)) != PB_OK) {
      return r;
    }
    uint32_t tri = s->triangle_count++;
    memcpy(s->triangles[tri], out, sizeof out);
    s->triangle_material[tri] = (uint32_t)J->mat;
  }
  return PB_OK;
}

/* Zero normals in the file (or collapsed by a degenerate transform): the
 * face normal of a triangle that uses the vertex. */
static void prim_fix_zero_normals(pb_scene *s, uint32_t tri_base) {
  for (uint32_t t = tri_base; t < s->triangle_count; ++t)
    for (int c = 0; c < 3; ++c) {
      uint32_t vi = s->triangles[t][c];
      float *Nn = s->normals[vi];
      if (Nn[0] == 0 && Nn[1] == 0 && Nn[2] == 0) {
        const float *a = s->positions[s->triangles[t][0]], *b = s->positions[s->triangles[t][1]],
                    *cc = s->positions[s->triangles[t][2]];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]};
        double fn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        if (!normalize3(fn)) fn[0] = 0, fn[1] = 0, fn[2] = 1;
        for (int a2 = 0; a2 < 3; ++a2) Nn[a2] = (float)fn[a2];
      }
    }
}

/* A rigid instance under an animated node: its range of the scene, posed
 * by pb_scene_set_time from the local vertices kept (anim.h). */
static pb_result prim_anim_range(loader *L, const prim_job *J, const prim_src *P) {
  pb_scene *s = L->s;
  struct pb_scene_anim *an = P->an;
  if (!an || s->vertex_count <= P->base) return PB_OK;
  if (an->range_count == an->range_cap) {
    uint32_t c = an->range_cap ? 2 * an->range_cap : 16;
    void *q = realloc(an->ranges, (size_t)c * sizeof *an->ranges);
    if (!q) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    an->ranges = q;
    an->range_cap = c;
  }
  an->ranges[an->range_count++] = (pb_anim_range){.node = J->node, .first_vertex = P->base, .vertex_count = s->vertex_count - P->base,
                                                  .first_tri = J->tri_base, .tri_count = s->triangle_count - J->tri_base,
                                                  .local = P->local, .flat = !P->has_n};
  an->local_count += s->vertex_count - P->base;
  return PB_OK;
}

/* meshes[mesh].primitives[pi] drawn by nodes[node] (world transform M):
 * checked whole (prim_check_*), then flattened into the scene. A primitive
 * that is not made of triangles, or makes none, is skipped with a warning. */
pb_result load_primitive(loader *L, int32_t node, int32_t mesh, size_t pi, const mat4 *M) {
  const pb_gltf_primitive *p = &L->doc->meshes[mesh].primitives[pi];
  if (p->mode != MODE_TRIANGLES && p->mode != MODE_TRIANGLE_STRIP && p->mode != MODE_TRIANGLE_FAN) {
    const char *mn = p->mode >= 0 && p->mode <= 6 ? mode_names[p->mode] : "unknown";
    return load_warn(L, "meshes[%d].primitives[%zu]: mode %d (%s) skipped: only triangles are rendered", mesh, pi, p->mode, mn);
  }
  if (p->position == -1)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: meshes[%d].primitives[%zu].attributes: no POSITION", L->path, mesh, pi);
  prim_job J;
  memset(&J, 0, sizeof J);
  J.p = p, J.node = node, J.mesh = mesh, J.pi = pi, J.M = M;
  prim_src P;
  memset(&P, 0, sizeof P);
  int skip = 0;
  pb_result r = prim_check_accessors(L, &J, &P);
  if (r == PB_OK) r = prim_check_material(L, &J, &P);
  if (r == PB_OK) r = prim_check_limits(L, &J, &P, &skip);
  if (r != PB_OK || skip) return r;

  pb_deform_src D;
  memset(&D, 0, sizeof D);
  if (J.deformed)
    r = pb_deform_read(L->path, L->doc, L->s, &L->deform, mesh, pi, J.skinned ? J.skin : -1, &P.pos, P.has_n ? &P.nrm : NULL,
                       P.use_t ? &P.tng : NULL, &D);
  if (r == PB_OK) r = prim_reserve(L, &J, &P);
  if (r == PB_OK) r = prim_begin(L, &J, &P, &D);
  if (r == PB_OK && P.has_n) r = prim_emit_vertices(L, &J, &P);
  if (r == PB_OK) r = prim_emit_triangles(L, &J, &P);
  if (r == PB_OK && P.has_n) prim_fix_zero_normals(L->s, J.tri_base);
  if (r == PB_OK) r = prim_anim_range(L, &J, &P);
  if (r == PB_OK && J.deformed) r = deform_add(L, node, &D, &P, J.tri_base);
  if (r == PB_OK && J.dropped)
    r = load_warn(L, "meshes[%d].primitives[%zu]: %llu degenerate triangles (repeated index) dropped", mesh, pi,
                  (unsigned long long)J.dropped);
  pb_deform_src_free(&D);
  free(P.src_of);
  return r;
}
/* After visit(): a scene with animation keeps the instances that move
 * (dynamic: an animated joint or mesh node, or animated weights) with the nodes visit() did not reach appended to the pose order
 * (joints outside the shown scene); everything else was posed once. */
pb_result load_deform_finish(loader *L) {
  pb_scene *s = L->s;
  pb_deform *df = &L->deform;
  struct pb_scene_anim *an = L->anim;
  s->skinned_vertex_count = df->skinned_vertices;
  s->morphed_vertex_count = df->morphed_vertices;
  uint32_t dynamic = 0;
  for (uint32_t i = 0; an && i < df->range_count; ++i) {
    pb_deform_range *R = &df->ranges[i];
    /* The mesh node counts for a skinned instance too: its vertices
     * without weight follow it (skin.c). */
    int moves = an->nodes[R->node].animated;
    if (R->target_count && an->nodes[R->node].weights_animated) moves = 1;
    for (uint32_t j = 0; R->skin >= 0 && j < df->skins[R->skin].joint_count; ++j)
      if (an->nodes[df->skins[R->skin].joints[j]].animated) moves = 1;
    R->dynamic = moves;
    dynamic += (uint32_t)moves;
    s->posed_vertex_count += moves ? R->vertex_count : 0;
  }
  if (!dynamic) {
    pb_deform_destroy(df);
    return PB_OK;
  }
  /* The pose order: visit()'s, then every node it did not reach, parents
   * first (node_state marks the visited ones). */
  pb_gltf_doc *d = L->doc;
  for (size_t n = 0; n < d->node_count; ++n) {
    if (L->node_state[n] || L->parent[n] >= 0) continue;
    size_t first = an->order_count;
    an->order[an->order_count++] = (int32_t)n;
    for (size_t k = first; k < an->order_count; ++k) {
      const pb_gltf_node *g = &d->nodes[an->order[k]];
      for (size_t c = 0; c < g->child_count; ++c) an->order[an->order_count++] = g->children[c];
    }
  }
  an->deform = malloc(sizeof *an->deform);
  if (!an->deform) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  *an->deform = *df; /* the anim owns it from here */
  memset(df, 0, sizeof *df);
  for (uint32_t i = 0; i < an->deform->range_count; ++i) {
    const pb_deform_range *R = &an->deform->ranges[i];
    if (!R->tan) continue;
    if (!an->tan_given && !(an->tan_given = calloc(s->vertex_count + 1, 1)))
      return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    memset(an->tan_given + R->first_vertex, 1, R->vertex_count);
  }
  return PB_OK;
}

/* Tangent frames for normal maps: only scenes with PB_FEATURE_NORMAL_MAPS
 * get s->tangents (the others pay nothing). The file's TANGENTs are kept,
 * every other vertex gets one from its uvs (tangents.c). */
pb_result load_tangents(loader *L) {
  pb_scene *s = L->s;
  if (!(s->features & (PB_FEATURE_NORMAL_MAPS | PB_FEATURE_ANISOTROPY)) || s->vertex_count == 0) return PB_OK;
  s->tangents = calloc(s->vertex_count, sizeof *s->tangents);
  uint8_t *given = calloc(s->vertex_count, 1);
  if (!s->tangents || !given) {
    free(given);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory for tangents", L->path);
  }
  for (uint32_t v = 0; v < s->vertex_count && v < L->tan_cap; ++v)
    if (L->tan_given[v]) {
      memcpy(s->tangents[v], L->tan[v], sizeof s->tangents[v]);
      given[v] = 1;
    }
  pb_result r = pb_tangents_generate((const float(*)[3])s->positions, (const float(*)[3])s->normals,
                                     (const float(*)[2])s->uvs, s->vertex_count,
                                     (const uint32_t(*)[3])s->triangles, s->triangle_count, given, s->tangents);
  free(given);
  return r;
}
