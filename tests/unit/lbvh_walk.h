/* The photon LBVH read back from the device (pb_photon_estimator_lbvh) and
 * checked on the host as the gather traverses it (shared/pb_lbvh.h), for
 * test_gpu_lbvh*.c. Include after pbtest.h. */
#ifndef PB_TEST_LBVH_WALK_H
#define PB_TEST_LBVH_WALK_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/gpu.h"
#include "render/photon/photon.h"
#include "render/photon/photon_pack.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"

/* lbvh_bounds.comp's T_auto (pb_t_auto: the threshold of least modelled
 * traversal cost) for k footprints over a point and n photons, in double. */
static inline uint32_t lbvh_t_auto_model(double k, uint32_t n) {
  double kp = (k > 0 ? k : 0) / M_PI, nf = n > 0 ? n : 1, best = INFINITY;
  uint32_t bt = 1;
  for (uint32_t t = 1; t <= PB_LBVH_MAX_LEAF; ++t) {
    double sl = fmax(t * 0.72134752, 1.0), sq = sqrt(sl) + 2.0 * sqrt(kp), cost = sq * sq;
    for (double sz = 2.0 * sl; sz < nf; sz *= 2.0) {
      double c = 1.0 + 2.0 * sqrt(kp / sz);
      cost += fmin(nf / sz, c * c);
    }
    if (cost < best) best = cost, bt = t;
  }
  return bt;
}

/* The last build, on the host. */
typedef struct lbvh_host {
  uint32_t n;
  pb_gpu_lbvh_info info;
  pb_gpu_lbvh_node *nodes;  /* n entries */
  pb_gpu_photon *photons;   /* n, Morton order, decoded from the packed records */
  uint32_t *keys, *order;   /* n each */
} lbvh_host;

/* What the walk found. Every count but the first three must be 0. */
typedef struct lbvh_walk {
  uint32_t leaves, max_leaf, inner;
  uint32_t not_once;        /* photons reached other than exactly once */
  uint32_t box;             /* photon AABBs or child boxes outside their box */
  uint32_t range;           /* children whose photon ranges do not tile their parent's */
  uint32_t big_leaf;        /* leaves over the threshold that are not one Morton code */
  uint32_t unmerged;        /* inner nodes of <= threshold photons or one code (should be leaves) */
  uint32_t bad_ref;         /* references outside the nodes, empty children */
  uint32_t deep;            /* deeper than the gather's stack */
  uint32_t split;           /* inner nodes not at their range's first differing key bit
                               (the radix tree's split: the smallest common prefix) */
} lbvh_walk;

/* Common prefix length of the sorted (code, index) keys i and i + 1
 * (Karras 2012's delta, as lbvh_climb.comp computes it). */
static inline int lbvh_delta(const lbvh_host *h, uint32_t i) {
  uint32_t a = h->keys[i], b = h->keys[i + 1];
  if (a != b) return __builtin_clz(a ^ b);
  return 32 + __builtin_clz(i ^ (i + 1));
}

static inline int lbvh_download(pb_gpu *g, pb_photon_estimator *e, lbvh_host *h) {
  memset(h, 0, sizeof *h);
  pb_photon_estimate_stats st;
  if (pb_photon_estimator_stats(g, e, &st) != PB_OK) return 0;
  pb_photon_lbvh_view v;
  pb_photon_estimator_lbvh(e, &v);
  uint32_t n = v.count, m = n ? n : 1;
  h->n = n;
  h->nodes = calloc(m, sizeof *h->nodes);
  h->photons = calloc(m, sizeof *h->photons);
  h->keys = calloc(m, sizeof *h->keys);
  h->order = calloc(m, sizeof *h->order);
  int ok = pb_gpu_buffer_download(g, v.info, 0, &h->info, sizeof h->info) == PB_OK;
  if (n && ok) {
    uint64_t off = (uint64_t)v.sorted_offset * 4;
    ok = pb_gpu_buffer_download(g, v.nodes, 0, h->nodes, (uint64_t)n * sizeof *h->nodes) == PB_OK &&
         pb_gpu_buffer_download(g, v.keys, off, h->keys, (uint64_t)n * 4) == PB_OK &&
         pb_gpu_buffer_download(g, v.order, off, h->order, (uint64_t)n * 4) == PB_OK;
    pb_gpu_photon_packed *q = calloc(n, sizeof *q);
    ok = ok && q && pb_gpu_buffer_download(g, v.photons, 0, q, (uint64_t)n * sizeof *q) == PB_OK;
    for (uint32_t i = 0; ok && i < n; ++i) pb_photon_unpack_host(&q[i], &h->photons[i]);
    free(q);
  }
  return ok;
}

static inline void lbvh_free(lbvh_host *h) {
  free(h->nodes), free(h->photons), free(h->keys), free(h->order);
  memset(h, 0, sizeof *h);
}

static inline void lbvh_photon_box(const pb_gpu_photon *p, float lo[3], float hi[3]) {
  for (int k = 0; k < 3; ++k) {
    float w = p->normal[k] * p->normal_extent;
    float e = sqrtf(p->axis_u[k] * p->axis_u[k] + p->axis_v[k] * p->axis_v[k] + w * w);
    lo[k] = p->position[k] - e;
    hi[k] = p->position[k] + e;
  }
}

static inline int lbvh_contains(const float lo[3], const float hi[3], const float l2[3], const float h2[3]) {
  for (int k = 0; k < 3; ++k) {
    float tol = 1e-5f * (1.0f + fabsf(lo[k]) + fabsf(hi[k]));
    if (l2[k] < lo[k] - tol || h2[k] > hi[k] + tol) return 0;
  }
  return 1;
}

/* One child entry that should cover sorted photons first .. first+count-1. */
static void lbvh_walk_child(const lbvh_host *h, const pb_gpu_lbvh_child *c, uint32_t first, uint32_t depth,
                            uint32_t *seen, lbvh_walk *w) {
  uint32_t t = h->info.t_auto, n = h->n;
  if (c->count == 0 || first + c->count > n) {
    w->bad_ref++;
    return;
  }
  if (depth > PB_LBVH_STACK) w->deep++;
  for (uint32_t i = first; i < first + c->count; ++i) {
    float lo[3], hi[3];
    lbvh_photon_box(&h->photons[i], lo, hi);
    if (!lbvh_contains(c->lo, c->hi, lo, hi)) w->box++;
  }
  uint32_t last = first + c->count - 1;
  if (c->ref & PB_LBVH_LEAF) {
    if ((c->ref & ~PB_LBVH_LEAF) != first) w->range++;
    for (uint32_t i = first; i <= last; ++i) seen[i]++;
    w->leaves++;
    if (c->count > w->max_leaf) w->max_leaf = c->count;
    if (c->count > t && h->keys[first] != h->keys[last]) w->big_leaf++;
    return;
  }
  uint32_t q = c->ref;
  if (q >= n - 1) {
    w->bad_ref++;
    return;
  }
  w->inner++;
  const pb_gpu_lbvh_node *nd = &h->nodes[q];
  /* Inner node q is the split after sorted photon q. */
  if (nd->child[0].count + nd->child[1].count != c->count || first + nd->child[0].count != q + 1) w->range++;
  if (c->count <= t || h->keys[first] == h->keys[last]) w->unmerged++;
  int dq = lbvh_delta(h, q);
  for (uint32_t i = first; i < last; ++i)
    if (i != q && lbvh_delta(h, i) <= dq) {
      w->split++;
      break;
    }
  for (int k = 0; k < 2; ++k)
    if (!lbvh_contains(c->lo, c->hi, nd->child[k].lo, nd->child[k].hi)) w->box++;
  lbvh_walk_child(h, &nd->child[0], first, depth + 1, seen, w);
  lbvh_walk_child(h, &nd->child[1], first + nd->child[0].count, depth + 1, seen, w);
}

static inline void lbvh_walk_tree(const lbvh_host *h, lbvh_walk *w) {
  memset(w, 0, sizeof *w);
  uint32_t n = h->n;
  if (n == 0) {
    if (h->info.root != PB_LBVH_NONE) w->bad_ref++;
    return;
  }
  uint32_t *seen = calloc(n, sizeof *seen);
  uint32_t r = h->info.root;
  if (r == n - 1) { /* the one-leaf root: child 0 the map, child 1 empty */
    const pb_gpu_lbvh_node *nd = &h->nodes[r];
    if (nd->child[1].count != 0 || !(nd->child[0].ref & PB_LBVH_LEAF)) w->bad_ref++;
    lbvh_walk_child(h, &nd->child[0], 0, 1, seen, w);
  } else if (r < n - 1) {
    const pb_gpu_lbvh_node *nd = &h->nodes[r];
    pb_gpu_lbvh_child root = {.ref = r, .count = n};
    for (int k = 0; k < 3; ++k) {
      root.lo[k] = fminf(nd->child[0].lo[k], nd->child[1].lo[k]);
      root.hi[k] = fmaxf(nd->child[0].hi[k], nd->child[1].hi[k]);
    }
    lbvh_walk_child(h, &root, 0, 0, seen, w);
  } else {
    w->bad_ref++;
  }
  for (uint32_t i = 0; i < n; ++i) w->not_once += seen[i] != 1;
  free(seen);
}

#endif
