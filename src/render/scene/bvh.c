/* Scene BVH: Embree's generic builder (rtcBuildBVH) makes the topology with
 * SAH; we flatten it into the compact GPU layout (see bvh.h). Binned SAH
 * (RTC_BUILD_QUALITY_MEDIUM), PB_BVH_WIDTH children per inner node, rather than spatial splits, so that every
 * triangle lives in exactly one leaf and leaves can store triangles inline. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>

#include "core/log.h"
#include "render/scene/bvh.h"

typedef struct tnode {
  int leaf;
  uint32_t count;              /* leaf: triangles; inner: children */
  struct tnode *child[PB_BVH_WIDTH];
  uint32_t prims[PB_BVH_MAX_LEAF];
} tnode;

static void *create_node(RTCThreadLocalAllocator alloc, unsigned int n, void *user) {
  (void)user;
  tnode *t = rtcThreadLocalAlloc(alloc, sizeof(tnode), 16);
  if (!t) return NULL;
  memset(t, 0, sizeof *t);
  t->count = n;
  return t;
}

static void set_children(void *node, void **children, unsigned int n, void *user) {
  (void)user;
  tnode *t = node;
  t->count = n > PB_BVH_WIDTH ? PB_BVH_WIDTH : n;
  for (unsigned i = 0; i < t->count; ++i) t->child[i] = children[i];
}

static void set_bounds(void *node, const struct RTCBounds **b, unsigned int n, void *user) {
  (void)node;
  (void)b;
  (void)n;
  (void)user; /* boxes are recomputed exactly from the triangles when flattening */
}

static void *create_leaf(RTCThreadLocalAllocator alloc, const struct RTCBuildPrimitive *p, size_t n,
                         void *user) {
  (void)user;
  if (n > PB_BVH_MAX_LEAF) return NULL;
  tnode *t = rtcThreadLocalAlloc(alloc, sizeof(tnode), 16);
  if (!t) return NULL;
  memset(t, 0, sizeof *t);
  t->leaf = 1;
  t->count = (uint32_t)n;
  for (size_t i = 0; i < n; ++i) t->prims[i] = p[i].primID;
  return t;
}

typedef struct flat {
  const pb_scene *s;
  pb_bvh *b;
  uint32_t max_depth;
  int bad;                     /* 1: malformed tree from the builder */
} flat;

static void box_add(float lo[3], float hi[3], const float p[3]) {
  for (int k = 0; k < 3; ++k) {
    lo[k] = fminf(lo[k], p[k]);
    hi[k] = fmaxf(hi[k], p[k]);
  }
}

/* Writes node `t` at index `at` (already reserved), recursing into children. */
static void flatten(flat *f, const tnode *t, uint32_t at, uint32_t depth) {
  pb_bvh *b = f->b;
  pb_gpu_bvh_node *n = &b->nodes[at];
  if (depth > f->max_depth) f->max_depth = depth;
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  if (!t || (!t->leaf && t->count == 0) || (t->leaf && t->count == 0)) {
    f->bad = 1;
    return;
  }
  /* An inner node with one child (the builder may emit one for tiny inputs):
   * collapse it into the child. */
  while (!t->leaf && t->count == 1) t = t->child[0];
  if (t->leaf) {
    n->first = b->tri_count;
    n->count = t->count;
    for (uint32_t i = 0; i < t->count; ++i) {
      uint32_t prim = t->prims[i];
      const uint32_t *tri = f->s->triangles[prim];
      pb_gpu_tri *g = &b->tris[b->tri_count++];
      memset(g, 0, sizeof *g);
      memcpy(g->p0, f->s->positions[tri[0]], sizeof g->p0);
      memcpy(g->p1, f->s->positions[tri[1]], sizeof g->p1);
      memcpy(g->p2, f->s->positions[tri[2]], sizeof g->p2);
      g->prim = prim;
      box_add(lo, hi, g->p0);
      box_add(lo, hi, g->p1);
      box_add(lo, hi, g->p2);
    }
    b->leaf_count++;
  } else {
    /* PB_BVH_WIDTH slots; unused ones stay empty (all zero, from calloc). */
    uint32_t c = b->node_count;
    b->node_count += PB_BVH_WIDTH;
    n = &b->nodes[at];
    n->first = c;
    n->count = 0;
    for (uint32_t k = 0; k < t->count; ++k) flatten(f, t->child[k], c + k, depth + 1);
    n = &b->nodes[at];
    for (uint32_t k = 0; k < t->count; ++k) {
      box_add(lo, hi, b->nodes[c + k].lo);
      box_add(lo, hi, b->nodes[c + k].hi);
    }
  }
  memcpy(n->lo, lo, sizeof lo);
  memcpy(n->hi, hi, sizeof hi);
}

void pb_bvh_destroy(pb_bvh *b) {
  if (!b) return;
  free(b->nodes);
  free(b->tris);
  memset(b, 0, sizeof *b);
}

static _Thread_local char embree_msg[256];
static void on_error(void *user, enum RTCError code, const char *str) {
  (void)user;
  if (!embree_msg[0]) snprintf(embree_msg, sizeof embree_msg, "Embree error %d: %s", (int)code, str ? str : "");
}

pb_result pb_bvh_build(const pb_scene *s, pb_bvh *out) {
  memset(out, 0, sizeof *out);
  const char *path = s->path ? s->path : "scene";
  if (s->triangle_count == 0) return pb_fail(PB_ERR_SCENE_EMPTY, "%s: no triangles to render", path);
  double t0 = pb_time_now();
  /* RTCBuildPrimitive is declared 32-byte aligned; malloc guarantees 16. */
  size_t bytes = ((size_t)s->triangle_count * sizeof(struct RTCBuildPrimitive) + 31) & ~(size_t)31;
  struct RTCBuildPrimitive *prims = aligned_alloc(32, bytes);
  if (!prims) return pb_fail(PB_ERR_NOMEM, "BVH: out of memory for %u triangles", s->triangle_count);
  size_t n = 0;
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    int finite = 1;
    for (int k = 0; k < 3; ++k) {
      uint32_t v = s->triangles[t][k];
      if (v >= s->vertex_count) {
        free(prims);
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: triangle %u uses vertex %u of %u", path, t, v,
                       s->vertex_count);
      }
      const float *p = s->positions[v];
      if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) finite = 0;
      box_add(lo, hi, p);
    }
    if (!finite) continue;
    prims[n++] = (struct RTCBuildPrimitive){
        .lower_x = lo[0], .lower_y = lo[1], .lower_z = lo[2], .geomID = 0,
        .upper_x = hi[0], .upper_y = hi[1], .upper_z = hi[2], .primID = t};
  }
  if (n == 0) {
    free(prims);
    return pb_fail(PB_ERR_SCENE_EMPTY, "%s: no triangle has finite vertices", path);
  }
  /* The traversal packs a node's first index with its count into 32 bits
   * (first < 2^29, see shaders/common/bvh.glsl); nodes < 2 n. */
  if (n >= (1u << 28)) {
    free(prims);
    return pb_fail(PB_ERR_LIMIT, "%s: %zu triangles exceed the GPU BVH's index range (2^28)", path, n);
  }
  pb_result r = PB_OK;
  embree_msg[0] = 0;
  RTCDevice dev = rtcNewDevice("verbose=0");
  RTCBVH bvh = dev ? rtcNewBVH(dev) : NULL;
  if (!dev || !bvh) {
    r = pb_fail(PB_ERR_INTERNAL, "BVH: Embree device creation failed");
    goto done;
  }
  rtcSetDeviceErrorFunction(dev, on_error, NULL);
  struct RTCBuildArguments a = rtcDefaultBuildArguments();
  a.buildQuality = RTC_BUILD_QUALITY_MEDIUM;
  a.maxBranchingFactor = PB_BVH_WIDTH;
  a.maxDepth = PB_BVH_MAX_DEPTH - 1; /* levels below the root; the traversal
                                        stack holds PB_BVH_WIDTH - 1 per level */
  a.sahBlockSize = 1;
  a.minLeafSize = 1;
  a.maxLeafSize = PB_BVH_MAX_LEAF;
  a.traversalCost = 1.0f;
  a.intersectionCost = 1.0f;
  a.bvh = bvh;
  a.primitives = prims;
  a.primitiveCount = n;
  a.primitiveArrayCapacity = n;
  a.createNode = create_node;
  a.setNodeChildren = set_children;
  a.setNodeBounds = set_bounds;
  a.createLeaf = create_leaf;
  tnode *root = rtcBuildBVH(&a);
  if (!root || embree_msg[0]) {
    r = pb_fail(PB_ERR_INTERNAL, "BVH: rtcBuildBVH failed: %s", embree_msg[0] ? embree_msg : "no root");
    goto done;
  }
  /* Inner nodes < n (at least two children each), PB_BVH_WIDTH slots each. */
  out->nodes = calloc(PB_BVH_WIDTH * n + 1, sizeof *out->nodes);
  out->tris = calloc(n, sizeof *out->tris);
  if (!out->nodes || !out->tris) {
    r = pb_fail(PB_ERR_NOMEM, "BVH: out of memory for %zu triangles", n);
    goto done;
  }
  flat f = {.s = s, .b = out};
  out->node_count = 1;
  flatten(&f, root, 0, 1);
  out->depth = f.max_depth;
  if (f.bad || out->tri_count != n) {
    r = pb_fail(PB_ERR_INTERNAL, "BVH: the builder returned a malformed tree (%u of %zu triangles placed)",
                out->tri_count, n);
    goto done;
  }
  if (out->depth > PB_BVH_MAX_DEPTH) {
    r = pb_fail(PB_ERR_LIMIT, "%s: BVH depth %u exceeds the GPU traversal stack (%u)", path, out->depth,
                (unsigned)PB_BVH_MAX_DEPTH);
    goto done;
  }
  out->build_s = pb_time_now() - t0;
done:
  if (bvh) rtcReleaseBVH(bvh);
  if (dev) rtcReleaseDevice(dev);
  free(prims);
  if (r != PB_OK) pb_bvh_destroy(out);
  return r;
}

/* ---- refit ----------------------------------------------------------------- */

pb_result pb_bvh_refit(const pb_scene *s, pb_bvh *b) {
  const char *path = s->path ? s->path : "scene";
  for (uint32_t i = 0; i < b->tri_count; ++i) {
    uint32_t prim = b->tris[i].prim;
    if (prim >= s->triangle_count)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: BVH refit: triangle %u of %u (not the scene the BVH was built from)", path,
                     prim, s->triangle_count);
    for (int k = 0; k < 3; ++k) {
      uint32_t v = s->triangles[prim][k];
      if (v >= s->vertex_count)
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: BVH refit: triangle %u uses vertex %u of %u", path, prim, v, s->vertex_count);
      const float *p = s->positions[v];
      if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: BVH refit: triangle %u is not finite", path, prim);
    }
  }
  for (uint32_t i = 0; i < b->tri_count; ++i) {
    pb_gpu_tri *g = &b->tris[i];
    const uint32_t *tri = s->triangles[g->prim];
    memcpy(g->p0, s->positions[tri[0]], sizeof g->p0);
    memcpy(g->p1, s->positions[tri[1]], sizeof g->p1);
    memcpy(g->p2, s->positions[tri[2]], sizeof g->p2);
  }
  for (uint32_t i = b->node_count; i-- > 0;) {
    pb_gpu_bvh_node *n = &b->nodes[i];
    if (n->count == 0 && n->first == 0) continue; /* empty child slot */
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    if (n->count > 0) {
      for (uint32_t k = 0; k < n->count; ++k) {
        const pb_gpu_tri *g = &b->tris[n->first + k];
        box_add(lo, hi, g->p0);
        box_add(lo, hi, g->p1);
        box_add(lo, hi, g->p2);
      }
    } else {
      for (uint32_t k = 0; k < PB_BVH_WIDTH; ++k) {
        const pb_gpu_bvh_node *c = &b->nodes[n->first + k];
        if (c->count == 0 && c->first == 0) continue;
        box_add(lo, hi, c->lo);
        box_add(lo, hi, c->hi);
      }
    }
    memcpy(n->lo, lo, sizeof lo);
    memcpy(n->hi, hi, sizeof hi);
  }
  return PB_OK;
}

static double box_area(const float lo[3], const float hi[3]) {
  double d[3];
  for (int k = 0; k < 3; ++k) d[k] = hi[k] > lo[k] ? (double)hi[k] - lo[k] : 0.0;
  return 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

double pb_bvh_sah_cost(const pb_bvh *b) {
  if (!b->node_count) return 0;
  double sum = 0;
  for (uint32_t i = 0; i < b->node_count; ++i) {
    const pb_gpu_bvh_node *n = &b->nodes[i];
    if (n->count == 0 && n->first == 0 && i != 0) continue;
    sum += box_area(n->lo, n->hi) * (n->count ? (double)n->count : 1.0);
  }
  return sum;
}

/* ---- structural check ---------------------------------------------------- */

static int box_eq(const float a[3], const float b[3]) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

int pb_bvh_check(const pb_bvh *b, char *why, size_t why_size) {
#define FAIL(...)                                                                                  \
  do {                                                                                             \
    snprintf(why, why_size, __VA_ARGS__);                                                          \
    ok = 0;                                                                                        \
    goto out;                                                                                      \
  } while (0)
  int ok = 1;
  uint8_t *seen = calloc(b->node_count ? b->node_count : 1, 1);
  uint8_t *tri_seen = calloc(b->tri_count ? b->tri_count : 1, 1);
  uint32_t *stack = malloc(sizeof(uint32_t) * PB_BVH_WIDTH * (b->node_count + 1));
  uint32_t *depth = malloc(sizeof(uint32_t) * PB_BVH_WIDTH * (b->node_count + 1));
  if (!seen || !tri_seen || !stack || !depth) FAIL("out of memory");
  if (b->node_count == 0) FAIL("no nodes");
  uint32_t sp = 0, reached = 0, max_depth = 0, empty = 0;
  stack[sp] = 0;
  depth[sp++] = 1;
  while (sp) {
    --sp;
    uint32_t i = stack[sp], d = depth[sp];
    if (i >= b->node_count) FAIL("node index %u out of range (%u nodes)", i, b->node_count);
    if (seen[i]) FAIL("node %u reached twice", i);
    seen[i] = 1;
    reached++;
    if (d > max_depth) max_depth = d;
    const pb_gpu_bvh_node *n = &b->nodes[i];
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    if (n->count > 0) {
      if (n->count > PB_BVH_MAX_LEAF) FAIL("leaf %u has %u triangles (max %u)", i, n->count, (unsigned)PB_BVH_MAX_LEAF);
      if (n->first > b->tri_count || n->count > b->tri_count - n->first)
        FAIL("leaf %u triangles %u..%u out of range", i, n->first, n->first + n->count);
      for (uint32_t k = 0; k < n->count; ++k) {
        uint32_t t = n->first + k;
        if (tri_seen[t]) FAIL("triangle slot %u in two leaves", t);
        tri_seen[t] = 1;
        box_add(lo, hi, b->tris[t].p0);
        box_add(lo, hi, b->tris[t].p1);
        box_add(lo, hi, b->tris[t].p2);
      }
    } else {
      uint32_t c = n->first;
      if (c == 0 || c >= b->node_count || b->node_count - c < PB_BVH_WIDTH)
        FAIL("inner node %u has child slots %u..%u out of range", i, c, c + PB_BVH_WIDTH - 1);
      if (c <= i) FAIL("inner node %u points backwards to %u (a cycle or shared child)", i, c);
      uint32_t kids = 0;
      for (uint32_t k = 0; k < PB_BVH_WIDTH; ++k) {
        const pb_gpu_bvh_node *ch = &b->nodes[c + k];
        if (ch->first == 0 && ch->count == 0) { /* empty slot */
          const float z[3] = {0, 0, 0};
          if (!box_eq(ch->lo, z) || !box_eq(ch->hi, z)) FAIL("empty slot %u has a box", c + k);
          if (seen[c + k]) FAIL("empty slot %u reached twice", c + k);
          seen[c + k] = 1;
          empty++;
          continue;
        }
        kids++;
        box_add(lo, hi, ch->lo);
        box_add(lo, hi, ch->hi);
        stack[sp] = c + k;
        depth[sp++] = d + 1;
      }
      if (kids < 2) FAIL("inner node %u has %u children", i, kids);
    }
    if (!box_eq(lo, n->lo) || !box_eq(hi, n->hi))
      FAIL("node %u box [%g %g %g]..[%g %g %g] is not the union of its %s [%g %g %g]..[%g %g %g]", i,
           n->lo[0], n->lo[1], n->lo[2], n->hi[0], n->hi[1], n->hi[2], n->count ? "triangles" : "children",
           lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  }
  if (reached + empty != b->node_count)
    FAIL("%u of %u nodes reachable from the root (%u empty slots)", reached, b->node_count, empty);
  for (uint32_t t = 0; t < b->tri_count; ++t)
    if (!tri_seen[t]) FAIL("triangle slot %u in no leaf", t);
  if (max_depth > PB_BVH_MAX_DEPTH) FAIL("depth %u exceeds %u", max_depth, (unsigned)PB_BVH_MAX_DEPTH);
out:
  free(seen);
  free(tri_seen);
  free(stack);
  free(depth);
  return ok;
#undef FAIL
}
