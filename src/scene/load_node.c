/* The node graph: checked to be a forest (load_check_nodes), every node's
 * rest world matrix, the precision origin, and the walk that flattens the
 * scene shown into the scene's arrays (load_scene_nodes: meshes, cameras,
 * lights per node). Part of the loader (load_internal.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/anim.h"
#include "scene/load_internal.h"

enum { MAX_NODE_DEPTH = 1024 };

/* The node graph must be a forest: every child index valid, no node with two
 * parents, no cycle (a cycle also shows up as a second parent, or as a root
 * that is someone's child). */
pb_result load_check_nodes(loader *L) {
  pb_gltf_doc *d = L->doc;
  for (size_t i = 0; i < d->node_count; ++i) L->parent[i] = -1;
  for (size_t i = 0; i < d->node_count; ++i) {
    const pb_gltf_node *n = &d->nodes[i];
    for (size_t c = 0; c < n->child_count; ++c) {
      int32_t ch = n->children[c];
      if (ch < 0 || (size_t)ch >= d->node_count)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].children[%zu]: node %d does not exist (%zu nodes)", L->path,
                       i, c, ch, d->node_count);
      if ((size_t)ch == i)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].children[%zu]: a node cannot be its own child", L->path, i, c);
      if (L->parent[ch] >= 0)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].children[%zu]: node %d already has parent nodes[%d] (the node graph must be a tree)",
                       L->path, i, c, ch, L->parent[ch]);
      L->parent[ch] = (int32_t)i;
    }
    if (!n->has_matrix) {
      for (int k = 0; k < 3; ++k)
        if (!isfinite(n->translation[k]) || !isfinite(n->scale[k]))
          return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu]: translation or scale is not finite", L->path, i);
      for (int k = 0; k < 4; ++k)
        if (!isfinite(n->rotation[k]))
          return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%zu].rotation: not finite", L->path, i);
    }
  }
  /* With one parent each, a cycle is a loop of parents: walk up from each
   * node until a node already known to reach a root (state 2); meeting a
   * node of the current walk (state 1) is a cycle. Linear in the node count,
   * so a long chain cannot stall us. node_state is left zeroed for visit(). */
  uint8_t *st = L->node_state;
  pb_result r = PB_OK;
  for (size_t i = 0; i < d->node_count && r == PB_OK; ++i) {
    int32_t p = (int32_t)i;
    while (p >= 0 && st[p] == 0) {
      st[p] = 1;
      p = L->parent[p];
    }
    if (p >= 0 && st[p] == 1)
      r = pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: cycle in the node graph", L->path, p);
    for (int32_t q = (int32_t)i; q >= 0 && st[q] == 1; q = L->parent[q]) st[q] = 2;
  }
  memset(st, 0, d->node_count);
  return r;
}

static pb_result visit(loader *L, int32_t node, const mat4 *parent, int depth) {
  pb_gltf_doc *d = L->doc;
  if (depth > MAX_NODE_DEPTH)
    return pb_fail(PB_ERR_LIMIT, "%s: nodes[%d]: node tree deeper than %d", L->path, node, MAX_NODE_DEPTH);
  if (L->node_state[node])
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: reached twice (listed in a scene and as a child?)", L->path, node);
  L->node_state[node] = 1;
  const pb_gltf_node *n = &d->nodes[node];
  struct pb_scene_anim *an = L->anim;
  if (an) an->order[an->order_count++] = node;
  mat4 local = load_node_local(n);
  mat4 M = mat_mul(parent, &local);
  if (!finite_mat(&M))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: transform is not finite", L->path, node);
  pb_result r = PB_OK;
  if (n->skin != -1 && (n->skin < 0 || (size_t)n->skin >= d->skin_count))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].skin: %d does not exist (%zu skins)", L->path, node, n->skin, d->skin_count);
  if (n->skin >= 0 && n->mesh == -1 &&
      (r = load_warn(L, "nodes[%d]: skin %d but no mesh; the skin is unused", node, n->skin)) != PB_OK)
    return r;
  if (n->mesh != -1) {
    if (n->mesh < 0 || (size_t)n->mesh >= d->mesh_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d].mesh: %d does not exist (%zu meshes)", L->path, node, n->mesh,
                     d->mesh_count);
    for (size_t pi = 0; pi < d->meshes[n->mesh].primitive_count; ++pi)
      if ((r = load_primitive(L, node, n->mesh, pi, &M)) != PB_OK) return r;
  }
  uint32_t nc = L->s->camera_count, nl = L->s->light_count;
  if (n->camera != -1 && (r = load_camera(L, node, &M)) != PB_OK) return r;
  if ((r = load_node_light(L, node, &M)) != PB_OK) return r;
  if (an && L->s->camera_count > nc && (r = load_anim_push_node(L, &an->camera_node, &an->camera_cap, nc, node)) != PB_OK) return r;
  if (an && L->s->light_count > nl && (r = load_anim_push_node(L, &an->light_node, &an->light_cap, nl, node)) != PB_OK) return r;
  for (size_t c = 0; c < n->child_count; ++c)
    if ((r = visit(L, n->children[c], &M, depth + 1)) != PB_OK) return r;
  return PB_OK;
}

/* ---- precision origin ---------------------------------------------------
 * Blender writes an object's location as its node's translation, so a scene
 * modelled far from the world origin (survey coordinates, a level at 1e5 m)
 * has world positions whose float spacing (1e5 m: 8 mm) moves edges and
 * defeats ray offsets. The world box of the mesh accessors' min/max (glTF
 * requires them on POSITION; when a primitive lacks them the scene is left
 * where it is) is found first, in double; when its centre lies more than
 * PRECISION_FAR box radii from the world origin, every world point (vertices,
 * cameras, lights) is computed relative to that centre, which scene.origin
 * records. Nothing is read here that visit() does not check again. */
enum { PRECISION_FAR = 8 };

static void extent_add(double box[6], const double p[3]) {
  for (int k = 0; k < 3; ++k) {
    if (p[k] < box[k]) box[k] = p[k];
    if (p[k] > box[3 + k]) box[3 + k] = p[k];
  }
}

static void world_extent(loader *L, int32_t node, const mat4 *parent, int depth, double box[6], int *unknown) {
  pb_gltf_doc *d = L->doc;
  if (depth > MAX_NODE_DEPTH || node < 0 || (size_t)node >= d->node_count) return;
  const pb_gltf_node *n = &d->nodes[node];
  mat4 local = load_node_local(n);
  mat4 M = mat_mul(parent, &local);
  if (!finite_mat(&M)) return;
  if (n->mesh >= 0 && (size_t)n->mesh < d->mesh_count) {
    const pb_gltf_mesh *m = &d->meshes[n->mesh];
    /* A skinned mesh ignores its node's transform: its bind pose maps
     * through the first joint (L->world holds the origin-free rest worlds
     * here, load()). */
    mat4 B = M;
    if (n->skin >= 0 && (uint32_t)n->skin < L->deform.skin_count) {
      const pb_skin *k = &L->deform.skins[n->skin];
      B = mat_mul(&L->world[k->joints[0]], &k->ibm[0]);
    }
    for (size_t pi = 0; pi < m->primitive_count; ++pi) {
      int32_t a = m->primitives[pi].position;
      double w[3];
      if (a >= 0 && (size_t)a < d->accessor_count && d->accessors[a].has_min_max) {
        const pb_gltf_accessor *ac = &d->accessors[a];
        for (int c = 0; c < 8; ++c) {
          double p[3] = {(c & 1) ? ac->max[0] : ac->min[0], (c & 2) ? ac->max[1] : ac->min[1],
                         (c & 4) ? ac->max[2] : ac->min[2]};
          xform_point(&B, p, w);
          if (isfinite(w[0]) && isfinite(w[1]) && isfinite(w[2])) extent_add(box, w);
        }
      } else {
        *unknown = 1;
      }
    }
  }
  for (size_t c = 0; c < n->child_count; ++c) world_extent(L, n->children[c], &M, depth + 1, box, unknown);
}

/* The translation every world point gets: -origin, or none. */
static void precision_origin(loader *L, const int32_t *roots, size_t count, double origin[3]) {
  mat4 I;
  memset(&I, 0, sizeof I);
  I.m[0] = I.m[5] = I.m[10] = I.m[15] = 1;
  double box[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
  int unknown = 0;
  for (size_t i = 0; i < count; ++i) world_extent(L, roots[i], &I, 0, box, &unknown);
  origin[0] = origin[1] = origin[2] = 0;
  if (unknown || !(box[0] <= box[3])) return;
  double c[3], r2 = 0, far = 0;
  for (int k = 0; k < 3; ++k) {
    c[k] = 0.5 * (box[k] + box[3 + k]);
    double e = 0.5 * (box[3 + k] - box[k]);
    r2 += e * e;
    if (fabs(c[k]) > far) far = fabs(c[k]);
  }
  if (r2 > 0 && far > PRECISION_FAR * sqrt(r2))
    for (int k = 0; k < 3; ++k) origin[k] = c[k];
}

/* Every node's world matrix in the file's pose, parents first (iterative:
 * a chain of nodes may be deeper than visit() allows, and the nodes outside
 * the shown scene count too: joints may be among them). `root` is the
 * roots' parent (the precision origin's translation). */
static pb_result load_rest_worlds(loader *L, const mat4 *root) {
  pb_gltf_doc *d = L->doc;
  if (!L->world) L->world = malloc((d->node_count + 1) * sizeof *L->world);
  int32_t *stack = malloc((d->node_count + 1) * sizeof *stack);
  if (!L->world || !stack) {
    free(stack);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
  }
  for (size_t n = 0; n < d->node_count; ++n) {
    if (L->parent[n] >= 0) continue;
    size_t top = 0;
    stack[top++] = (int32_t)n;
    while (top) {
      int32_t k = stack[--top];
      mat4 local = load_node_local(&d->nodes[k]);
      L->world[k] = mat_mul(L->parent[k] >= 0 ? &L->world[L->parent[k]] : root, &local);
      /* A forest (load_check_nodes): each node is pushed once, so top stays
       * below node_count. */
      for (size_t c = 0; c < d->nodes[k].child_count; ++c) stack[top++] = d->nodes[k].children[c];
    }
  }
  free(stack);
  pb_skins_update(&L->deform, L->world);
  return PB_OK;
}

/* The scene to show (`scene`, else scenes[0], else every root node) walked
 * into the scene's arrays, after the rest worlds and the precision origin. */
pb_result load_scene_nodes(loader *L) {
  pb_gltf_doc *d = L->doc;
  pb_scene *s = L->s;
  pb_result r;
  mat4 I;
  memset(&I, 0, sizeof I);
  I.m[0] = I.m[5] = I.m[10] = I.m[15] = 1;
  /* The rest worlds without the precision origin first: the origin's
   * estimate reads skinned meshes through their joints. */
  if ((r = load_rest_worlds(L, &I)) != PB_OK) return r;
  if (d->default_scene != -1 && (d->default_scene < 0 || (size_t)d->default_scene >= d->scene_count))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: scene: %d does not exist (%zu scenes)", L->path, d->default_scene, d->scene_count);
  if (d->scene_count > 0) {
    int32_t si = d->default_scene != -1 ? d->default_scene : 0;
    const pb_gltf_scene *sc = &d->scenes[si];
    precision_origin(L, sc->nodes, sc->node_count, s->origin);
    I.m[12] = -s->origin[0], I.m[13] = -s->origin[1], I.m[14] = -s->origin[2];
    if ((r = load_rest_worlds(L, &I)) != PB_OK) return r;
    for (size_t i = 0; i < sc->node_count; ++i) {
      int32_t n = sc->nodes[i];
      if (n < 0 || (size_t)n >= d->node_count)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: scenes[%d].nodes[%zu]: node %d does not exist (%zu nodes)", L->path, si, i,
                       n, d->node_count);
      if (L->parent[n] >= 0)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: scenes[%d].nodes[%zu]: node %d is not a root (it is a child of nodes[%d])",
                       L->path, si, i, n, L->parent[n]);
      if ((r = visit(L, n, &I, 0)) != PB_OK) return r;
    }
  } else {
    if (d->node_count && (r = load_warn(L, "scenes: none; every root node is shown")) != PB_OK) return r;
    int32_t *roots = malloc((d->node_count + 1) * sizeof *roots);
    if (!roots) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", L->path);
    size_t nr = 0;
    for (size_t n = 0; n < d->node_count; ++n)
      if (L->parent[n] < 0) roots[nr++] = (int32_t)n;
    precision_origin(L, roots, nr, s->origin);
    free(roots);
    I.m[12] = -s->origin[0], I.m[13] = -s->origin[1], I.m[14] = -s->origin[2];
    if ((r = load_rest_worlds(L, &I)) != PB_OK) return r;
    for (size_t n = 0; n < d->node_count; ++n)
      if (L->parent[n] < 0 && (r = visit(L, (int32_t)n, &I, 0)) != PB_OK) return r;
  }
  return PB_OK;
}
