/* Ray-robustness hard cases shared by test_hard_rays_cpu.c (Embree, the
 * reference renderer's accel) and test_hard_rays_gpu.c (the GPU ray kernel):
 *
 *  self-intersection (pbrt-v4's Triangle.Reintersect, scaled up): random
 *    (triangle, barycentric) points made real hits by a ray from 1/100 of
 *    the triangle's size outside (the hit's barycentrics are used when it
 *    hits that triangle), the surface point reconstructed as the renderer
 *    does (pb_surface_from_hit: float interpolation of the float vertices),
 *    the origin moved off with pb_offset_ray along the geometric normal on
 *    the side of the outgoing direction (reflection or transmission side),
 *    and a ray traced in a random direction of that hemisphere, half of them
 *    grazing (elevation log-uniform in [1e-6 rad, 0.1 degree]). A hit on the
 *    same triangle is a self-hit. Directions are drawn around the renderer's
 *    float normal; the few whose float direction does not leave the exact
 *    plane of the float vertices (slivers, whose float normal is off by up
 *    to ~1e-4 rad) may cross it legitimately and are counted apart.
 *  watertightness (Embree's WatertightTest, aimed): closed convex meshes
 *    (icosphere, cube) hit at exact vertices, within 1e-7 and 1e-5 of an
 *    edge's length from a vertex, and at points along edges, from outside
 *    (directions entering the solid there through every face at the point,
 *    by a margin) and from inside outward; plus Embree's own test, random
 *    rays from points inside. The first hit must be the boundary crossing
 *    at the expected distance (the exact interval of the float ray inside
 *    the solid decides where the quick check is unsure); anything else is a
 *    miss. An outside float ray whose line does not pass through the solid
 *    (origin rounding at a corner) is ill-posed and not judged.
 *
 * Both run through a batch trace callback so the two renderers answer the
 * same rays. Header-only (static functions). */
#ifndef PB_TEST_HARD_RAYS_H
#define PB_TEST_HARD_RAYS_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ref/accel.h"
#include "ref/bsdf.h"
#include "ref/lights.h"
#include "scene/scene.h"
#include "shared/pb_gpu.h"
#include "test_ref_scene.h"

/* Traces n rays (tmin 0, tmax finite): hits[i].prim = PB_GPU_MISS on a miss.
 * Returns 0 on failure. */
typedef int (*hr_trace_fn)(void *user, const pb_gpu_ray *rays, uint32_t n, pb_gpu_hit *hits);

/* Rays per traced batch. */
#define HR_BATCH 65536u
/* Rays per set per watertight mesh. */
#define HR_WATER_RAYS 65536u
/* tmax of every ray: finite, so that a miss's t is finite too. */
#define HR_TMAX 1e30f

/* ---- random numbers (splitmix64) ----------------------------------------- */

static inline double hr_rand(uint64_t *st) {
  uint64_t z = (*st += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static inline void hr_sphere(uint64_t *st, double d[3]) {
  double z = 2 * hr_rand(st) - 1, phi = 2 * M_PI * hr_rand(st), q = sqrt(fmax(0, 1 - z * z));
  d[0] = q * cos(phi);
  d[1] = q * sin(phi);
  d[2] = z;
}

/* ---- double-precision helpers ------------------------------------------- */

static inline double hr_dot(const double a[3], const double b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline double hr_norm(double a[3]) {
  double l = sqrt(hr_dot(a, a));
  if (l > 0)
    for (int k = 0; k < 3; ++k) a[k] /= l;
  return l;
}

/* Unit normal (double) of triangle t's float vertices, counter-clockwise;
 * returns twice the area (0 for a degenerate triangle). */
static inline double hr_tri_normal(const pb_scene *s, uint32_t t, double n[3]) {
  const float *p0 = s->positions[s->triangles[t][0]], *p1 = s->positions[s->triangles[t][1]],
              *p2 = s->positions[s->triangles[t][2]];
  double e1[3], e2[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = (double)p1[k] - p0[k];
    e2[k] = (double)p2[k] - p0[k];
  }
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  return hr_norm(n);
}

static inline double hr_longest_edge(const pb_scene *s, uint32_t t) {
  double lmax = 0;
  for (int i = 0; i < 3; ++i) {
    const float *a = s->positions[s->triangles[t][i]], *b = s->positions[s->triangles[t][(i + 1) % 3]];
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += ((double)b[k] - a[k]) * ((double)b[k] - a[k]);
    lmax = fmax(lmax, sqrt(d2));
  }
  return lmax;
}

static inline int hr_hit_finite(const pb_gpu_hit *h) {
  return isfinite(h->t) && isfinite(h->u) && isfinite(h->v);
}

/* ---- code-built scenes --------------------------------------------------- */

/* Allocates vertex and triangle arrays for a code-built scene with one
 * Lambertian material; normals are filled by hr_finish. */
static inline void hr_alloc(pb_scene *s, uint32_t nv, uint32_t nt) {
  tsc_init(s);
  tsc_material(s, tsc_lambert(0.5f, 0.5f, 0.5f));
  s->vertex_count = nv;
  s->triangle_count = nt;
  s->positions = calloc(nv ? nv : 1, sizeof *s->positions);
  s->normals = calloc(nv ? nv : 1, sizeof *s->normals);
  s->uvs = calloc(nv ? nv : 1, sizeof *s->uvs);
  s->triangles = calloc(nt ? nt : 1, sizeof *s->triangles);
  s->triangle_material = calloc(nt ? nt : 1, sizeof *s->triangle_material);
  if (!s->positions || !s->normals || !s->uvs || !s->triangles || !s->triangle_material) {
    fprintf(stderr, "out of memory\n");
    abort();
  }
}

/* Bounds and per-vertex normals (the normal of the last triangle using it;
 * the ray tests only read geometric normals). */
static inline void hr_finish(pb_scene *s) {
  for (int k = 0; k < 3; ++k) {
    s->bounds_min[k] = INFINITY;
    s->bounds_max[k] = -INFINITY;
  }
  for (uint32_t i = 0; i < s->vertex_count; ++i)
    for (int k = 0; k < 3; ++k) {
      s->bounds_min[k] = fminf(s->bounds_min[k], s->positions[i][k]);
      s->bounds_max[k] = fmaxf(s->bounds_max[k], s->positions[i][k]);
      s->normals[i][k] = k == 2 ? 1.0f : 0.0f;
    }
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    double n[3];
    if (hr_tri_normal(s, t, n) > 0)
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) s->normals[s->triangles[t][i]][k] = (float)n[k];
  }
}

/* A soup of n independent random triangles with centres in a cube of side
 * `scale` around `center`: circumradii log-uniform over two decades below
 * size x scale, a third of them slivers (the third vertex 1e-3 of the
 * circumradius off the first edge). */
static inline void hr_soup(pb_scene *s, uint64_t seed, uint32_t n, double scale, double size, const double center[3]) {
  hr_alloc(s, 3 * n, n);
  uint64_t st = seed;
  for (uint32_t t = 0; t < n; ++t) {
    double c[3], v[3][3], r = scale * size * pow(10.0, -2.0 * hr_rand(&st));
    for (int k = 0; k < 3; ++k) c[k] = center[k] + scale * (hr_rand(&st) - 0.5);
    int sliver = hr_rand(&st) < 1.0 / 3.0;
    for (int i = 0; i < 3; ++i) {
      double d[3];
      hr_sphere(&st, d);
      for (int k = 0; k < 3; ++k) v[i][k] = c[k] + r * d[k];
    }
    if (sliver) {
      double a = hr_rand(&st), d[3];
      hr_sphere(&st, d);
      for (int k = 0; k < 3; ++k) v[2][k] = v[0][k] + a * (v[1][k] - v[0][k]) + 1e-3 * r * d[k];
    }
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) s->positions[3 * t + i][k] = (float)v[i][k];
      s->triangles[t][i] = 3 * t + (uint32_t)i;
    }
  }
  hr_finish(s);
}

/* Closed meshes, counter-clockwise seen from outside, positions
 * center + scale * unit-mesh rounded to float once. */
static inline void hr_place(pb_scene *s, const double (*unit)[3], double scale, const double center[3]) {
  for (uint32_t i = 0; i < s->vertex_count; ++i)
    for (int k = 0; k < 3; ++k) s->positions[i][k] = (float)(center[k] + scale * unit[i][k]);
  hr_finish(s);
}

/* The cube [-1, 1]^3 times scale: 8 vertices, 12 triangles. */
static inline void hr_cube(pb_scene *s, double scale, const double center[3]) {
  static const double v[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                 {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  static const uint32_t q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                   {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  hr_alloc(s, 8, 12);
  for (int f = 0; f < 6; ++f) {
    /* Alternate the diagonal so both diagonals of a quad occur. */
    const uint32_t *a = q[f];
    uint32_t t = 2u * (uint32_t)f;
    if (f & 1) {
      s->triangles[t][0] = a[0], s->triangles[t][1] = a[1], s->triangles[t][2] = a[2];
      s->triangles[t + 1][0] = a[0], s->triangles[t + 1][1] = a[2], s->triangles[t + 1][2] = a[3];
    } else {
      s->triangles[t][0] = a[0], s->triangles[t][1] = a[1], s->triangles[t][2] = a[3];
      s->triangles[t + 1][0] = a[1], s->triangles[t + 1][1] = a[2], s->triangles[t + 1][2] = a[3];
    }
  }
  hr_place(s, v, scale, center);
}

/* Icosahedron subdivided `level` times (midpoints pushed to the unit
 * sphere), times scale: 10 4^level + 2 vertices, 20 4^level triangles. */
static inline void hr_icosphere(pb_scene *s, int level, double scale, const double center[3]) {
  uint32_t nt = 20u << (2 * level), nv = 10u * (1u << (2 * level)) + 2u;
  double(*v)[3] = calloc(nv, sizeof *v);
  uint32_t(*tri)[3] = calloc(nt, sizeof *tri), (*tmp)[3] = calloc(nt, sizeof *tmp);
  /* Edge midpoint cache: for each vertex a short list of (other, mid). */
  uint32_t *key = calloc((size_t)nv * 8, sizeof *key), *mid = calloc((size_t)nv * 8, sizeof *mid);
  if (!v || !tri || !tmp || !key || !mid) abort();
  const double g = (1 + sqrt(5.0)) / 2;
  const double iv[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                            {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  const uint32_t it[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                              {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                              {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                              {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  uint32_t cv = 12, ct = 20;
  for (int i = 0; i < 12; ++i) {
    memcpy(v[i], iv[i], sizeof v[i]);
    hr_norm(v[i]);
  }
  memcpy(tri, it, sizeof it);
  for (int l = 0; l < level; ++l) {
    memset(key, 0xff, (size_t)nv * 8 * sizeof *key);
    uint32_t nt2 = 0;
    for (uint32_t t = 0; t < ct; ++t) {
      uint32_t m[3];
      for (int e = 0; e < 3; ++e) {
        uint32_t a = tri[t][e], b = tri[t][(e + 1) % 3], lo = a < b ? a : b, hi = a < b ? b : a;
        uint32_t j = 0;
        while (j < 8 && key[lo * 8 + j] != UINT32_MAX && key[lo * 8 + j] != hi) ++j;
        if (j == 8) abort();
        if (key[lo * 8 + j] == hi) {
          m[e] = mid[lo * 8 + j];
        } else {
          for (int k = 0; k < 3; ++k) v[cv][k] = 0.5 * (v[a][k] + v[b][k]);
          hr_norm(v[cv]);
          key[lo * 8 + j] = hi;
          mid[lo * 8 + j] = cv;
          m[e] = cv++;
        }
      }
      uint32_t a = tri[t][0], b = tri[t][1], c = tri[t][2];
      const uint32_t sub[4][3] = {{a, m[0], m[2]}, {m[0], b, m[1]}, {m[2], m[1], c}, {m[0], m[1], m[2]}};
      memcpy(&tmp[nt2], sub, sizeof sub);
      nt2 += 4;
    }
    ct = nt2;
    memcpy(tri, tmp, (size_t)ct * sizeof *tri);
  }
  if (cv != nv || ct != nt) abort();
  hr_alloc(s, nv, nt);
  memcpy(s->triangles, tri, (size_t)nt * sizeof *tri);
  hr_place(s, (const double(*)[3])v, scale, center);
  free(v);
  free(tri);
  free(tmp);
  free(key);
  free(mid);
}

/* 1 when every directed edge occurs once and its reverse once (a closed,
 * consistently wound 2-manifold). */
static inline int hr_closed(const pb_scene *s) {
  uint32_t ne = 3 * s->triangle_count;
  uint64_t *e = malloc((size_t)ne * 2 * sizeof *e);
  if (!e) abort();
  for (uint32_t t = 0; t < s->triangle_count; ++t)
    for (int i = 0; i < 3; ++i) {
      uint64_t a = s->triangles[t][i], b = s->triangles[t][(i + 1) % 3];
      e[2 * (3 * t + (uint32_t)i)] = (a << 32) | b;     /* directed */
      e[2 * (3 * t + (uint32_t)i) + 1] = (b << 32) | a; /* its reverse */
    }
  /* Each directed edge must occur exactly twice in this list: once itself,
   * once as the reverse of its twin. */
  int ok = 1;
  for (uint32_t i = 0; i < ne && ok; ++i) {
    uint32_t c = 0;
    for (uint32_t j = 0; j < 2 * ne; ++j) c += e[j] == e[2 * i];
    ok = c == 2;
  }
  free(e);
  return ok;
}

/* ---- batched tracing ----------------------------------------------------- */

static inline int hr_trace_all(hr_trace_fn fn, void *user, const pb_gpu_ray *rays, uint32_t n, pb_gpu_hit *hits) {
  for (uint32_t i = 0; i < n; i += HR_BATCH) {
    uint32_t m = n - i < HR_BATCH ? n - i : HR_BATCH;
    if (!fn(user, rays + i, m, hits + i)) return 0;
  }
  return 1;
}

static inline void hr_ray(pb_gpu_ray *r, const double o[3], const double d[3]) {
  memset(r, 0, sizeof *r);
  double dd[3] = {d[0], d[1], d[2]};
  hr_norm(dd);
  for (int k = 0; k < 3; ++k) {
    r->org[k] = (float)o[k];
    r->dir[k] = (float)dd[k];
  }
  r->tmin = 0.0f;
  r->tmax = HR_TMAX;
}

/* ---- self-intersection --------------------------------------------------- */

typedef struct hr_self_stats {
  uint64_t rays;          /* secondary rays traced */
  uint64_t grazing;       /* of those, elevation <= 0.1 degree */
  uint64_t primary_hits;  /* points that are the primary ray's own hit */
  uint64_t judged;        /* rays whose float direction leaves the exact plane */
  uint64_t below_plane;   /* float direction at or below the exact plane (not judged) */
  uint64_t self_hits;     /* judged rays hitting their own triangle */
  uint64_t self_hits_grazing;
  uint64_t self_hits_unjudged; /* self-hits among below_plane rays (report only) */
  uint64_t origin_not_lifted;  /* offset origin not strictly on its side of the exact plane */
  uint64_t near_neighbour;     /* hits at t < 1e-4 longest edge on a triangle sharing a vertex position */
  uint64_t nonfinite;          /* non-finite origin, direction, or hit t/u/v */
  double min_elevation;        /* smallest exact elevation judged, radians */
} hr_self_stats;

/* Does triangle b share a vertex position (bitwise) with triangle a? */
static inline int hr_share_vertex(const pb_scene *s, uint32_t a, uint32_t b) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!memcmp(s->positions[s->triangles[a][i]], s->positions[s->triangles[b][j]], sizeof(float[3])))
        return 1;
  return 0;
}

/* n random points (triangles uniform by index among non-degenerate ones),
 * one outgoing ray each. Returns 0 when tracing failed. */
static inline int hr_self_test(const pb_scene *s, const char *name, uint32_t n, uint64_t seed, hr_trace_fn fn,
                               void *user, hr_self_stats *st) {
  memset(st, 0, sizeof *st);
  st->min_elevation = INFINITY;
  const double max_graze = 0.1 * M_PI / 180.0, min_graze = 1e-6;
  uint32_t *tris = malloc(HR_BATCH * sizeof *tris);
  float(*uv)[2] = malloc(HR_BATCH * sizeof *uv);
  double(*nx)[3] = malloc(HR_BATCH * sizeof *nx); /* exact normal, facing the outgoing side */
  double *elev = malloc(HR_BATCH * sizeof *elev), *edge = malloc(HR_BATCH * sizeof *edge);
  unsigned char *graze = malloc(HR_BATCH);
  pb_gpu_ray *rays = malloc(HR_BATCH * sizeof *rays);
  pb_gpu_hit *hits = malloc(HR_BATCH * sizeof *hits);
  if (!tris || !uv || !nx || !elev || !edge || !graze || !rays || !hits) abort();
  uint64_t rs = seed;
  int ok = 1;
  for (uint32_t base = 0; base < n && ok; base += HR_BATCH) {
    uint32_t m = n - base < HR_BATCH ? n - base : HR_BATCH;
    /* Primary rays: from outside, at the point, from either side, at least
     * 17 degrees off the plane, from 1/100 of the longest edge away. */
    for (uint32_t i = 0; i < m; ++i) {
      uint32_t t;
      double nt[3];
      do {
        t = (uint32_t)(hr_rand(&rs) * s->triangle_count) % s->triangle_count;
      } while (!(hr_tri_normal(s, t, nt) > 0));
      float u = (float)hr_rand(&rs), v = (float)hr_rand(&rs);
      if (u + v > 1.0f) {
        u = 1.0f - u;
        v = 1.0f - v;
      }
      tris[i] = t;
      uv[i][0] = u;
      uv[i][1] = v;
      edge[i] = hr_longest_edge(s, t);
      const float *p0 = s->positions[s->triangles[t][0]], *p1 = s->positions[s->triangles[t][1]],
                  *p2 = s->positions[s->triangles[t][2]];
      double x[3], w[3], o[3], d[3];
      for (int k = 0; k < 3; ++k) x[k] = (1.0 - u - v) * p0[k] + (double)u * p1[k] + (double)v * p2[k];
      do hr_sphere(&rs, w);
      while (fabs(hr_dot(w, nt)) < 0.3);
      for (int k = 0; k < 3; ++k) {
        o[k] = x[k] + 0.01 * edge[i] * w[k];
        d[k] = -w[k];
      }
      hr_ray(&rays[i], o, d);
    }
    if (!hr_trace_all(fn, user, rays, m, hits)) {
      ok = 0;
      break;
    }
    /* Secondary rays from the renderer's surface point. */
    for (uint32_t i = 0; i < m; ++i) {
      uint32_t t = tris[i];
      pb_ref_hit h = {.t = 1.0f, .prim = t, .u = uv[i][0], .v = uv[i][1]};
      if (hits[i].prim == t && hr_hit_finite(&hits[i])) {
        h.u = hits[i].u;
        h.v = hits[i].v;
        st->primary_hits++;
      }
      if (hits[i].prim != PB_GPU_MISS && !hr_hit_finite(&hits[i])) st->nonfinite++;
      pb_surface surf;
      v3 in = v3_load(rays[i].dir);
      pb_surface_from_hit(s, &h, in, &surf);
      int transmit = hr_rand(&rs) < 0.5;
      v3 n_out = transmit ? v3_neg(surf.ng) : surf.ng;
      v3 tb, bb;
      v3_basis(n_out, &tb, &bb);
      double e, phi = 2 * M_PI * hr_rand(&rs);
      graze[i] = hr_rand(&rs) < 0.5;
      if (graze[i]) e = min_graze * pow(max_graze / min_graze, hr_rand(&rs));
      else e = asin(hr_rand(&rs)); /* uniform on the hemisphere */
      double d[3], o[3];
      for (int k = 0; k < 3; ++k)
        d[k] = cos(e) * (cos(phi) * v3_get(tb, k) + sin(phi) * v3_get(bb, k)) + sin(e) * v3_get(n_out, k);
      v3 org = pb_offset_ray(surf.p, n_out);
      for (int k = 0; k < 3; ++k) o[k] = v3_get(org, k);
      hr_ray(&rays[i], o, d);
      if (!v3_finite(org) || !isfinite(rays[i].dir[0] + rays[i].dir[1] + rays[i].dir[2])) st->nonfinite++;
      /* Judge against the exact plane of the float vertices. */
      double ne[3];
      hr_tri_normal(s, t, ne);
      double sgn = hr_dot(ne, (double[3]){n_out.x, n_out.y, n_out.z}) < 0 ? -1.0 : 1.0;
      for (int k = 0; k < 3; ++k) nx[i][k] = sgn * ne[k];
      double df[3] = {rays[i].dir[0], rays[i].dir[1], rays[i].dir[2]};
      elev[i] = asin(fmax(-1.0, fmin(1.0, hr_dot(df, nx[i]) / sqrt(hr_dot(df, df)))));
      const float *p0 = s->positions[s->triangles[t][0]];
      double rel[3] = {(double)org.x - p0[0], (double)org.y - p0[1], (double)org.z - p0[2]};
      if (!(hr_dot(rel, nx[i]) > 0)) st->origin_not_lifted++;
    }
    if (!hr_trace_all(fn, user, rays, m, hits)) {
      ok = 0;
      break;
    }
    for (uint32_t i = 0; i < m; ++i) {
      uint32_t t = tris[i];
      const pb_gpu_hit *h = &hits[i];
      int hit = h->prim != PB_GPU_MISS;
      if (hit && !hr_hit_finite(h)) st->nonfinite++;
      st->rays++;
      st->grazing += graze[i];
      int judged = elev[i] > 0;
      if (!judged) {
        st->below_plane++;
        st->self_hits_unjudged += hit && h->prim == t;
        continue;
      }
      st->judged++;
      if (elev[i] < st->min_elevation) st->min_elevation = elev[i];
      if (hit && h->prim == t) {
        if (st->self_hits++ < 10)
          fprintf(stderr,
                  "%s: self-hit: triangle %u, org (%.9g %.9g %.9g) dir (%.9g %.9g %.9g), t %.9g, "
                  "elevation %.3g rad, longest edge %.3g\n",
                  name, t, rays[i].org[0], rays[i].org[1], rays[i].org[2], rays[i].dir[0], rays[i].dir[1],
                  rays[i].dir[2], h->t, elev[i], edge[i]);
        st->self_hits_grazing += graze[i];
      } else if (hit && h->t < 1e-4 * edge[i] && hr_share_vertex(s, t, h->prim)) {
        st->near_neighbour++;
      }
    }
  }
  free(tris);
  free(uv);
  free(nx);
  free(elev);
  free(edge);
  free(graze);
  free(rays);
  free(hits);
  return ok;
}

static inline void hr_self_print(const char *who, const char *name, const hr_self_stats *st) {
  printf("%s %-22s self: %llu rays (%llu grazing), %llu primary hits, %llu judged, %llu below the exact plane; "
         "self-hits %llu (grazing %llu; unjudged %llu); origins not lifted %llu; near-neighbour hits %llu; "
         "non-finite %llu; min elevation %.2g rad\n",
         who, name, (unsigned long long)st->rays, (unsigned long long)st->grazing,
         (unsigned long long)st->primary_hits, (unsigned long long)st->judged,
         (unsigned long long)st->below_plane, (unsigned long long)st->self_hits,
         (unsigned long long)st->self_hits_grazing, (unsigned long long)st->self_hits_unjudged,
         (unsigned long long)st->origin_not_lifted, (unsigned long long)st->near_neighbour,
         (unsigned long long)st->nonfinite, st->min_elevation);
}

/* ---- watertightness ------------------------------------------------------ */

/* Ray sets: aimed at targets from outside, from inside outward, and (Embree's
 * WatertightTest) random directions from random points inside. Targets:
 * exact vertices, points within 1e-7 or 1e-5 of an edge's length from a
 * vertex, and points along edges. */
enum { HR_OUT = 0, HR_IN = 1, HR_RANDOM = 2, HR_SETS = 3 };
enum { HR_VERTEX = 0, HR_NEAR_VERTEX = 1, HR_EDGE = 2, HR_KINDS = 3 };
static const char *const hr_set_name[HR_SETS] = {"outside", "inside", "random-inside"};
static const char *const hr_kind_name[HR_KINDS] = {"vertex", "near-vertex", "edge"};

typedef struct hr_water_stats {
  uint64_t rays[HR_SETS][HR_KINDS], misses[HR_SETS][HR_KINDS];
  uint64_t ill_posed; /* outside rays whose float line does not pass through
                         the solid (rounding of the origin at a corner): not judged */
  uint64_t nonfinite;
} hr_water_stats;

/* Edge parameters (distance from the nearer end over the edge length); the
 * last entry stands for a uniform random one. */
static const double hr_edge_s[] = {0.0, 1e-7, 1e-5, 1e-3, 0.1, 0.3, 0.5, -1.0};

/* The exact (double) interval of the float ray's line inside the convex
 * solid (intersection of the triangles' half-spaces); empty when tin >= tout. */
static inline void hr_interval(const pb_scene *s, const double (*nrm)[3], const pb_gpu_ray *r, double *tin,
                               double *tout) {
  double lo = -INFINITY, hi = INFINITY;
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    const float *p = s->positions[s->triangles[t][0]];
    double dn = nrm[t][0] * r->dir[0] + nrm[t][1] * r->dir[1] + nrm[t][2] * r->dir[2];
    double on = nrm[t][0] * ((double)r->org[0] - p[0]) + nrm[t][1] * ((double)r->org[1] - p[1]) +
                nrm[t][2] * ((double)r->org[2] - p[2]); /* signed distance, outward positive */
    if (dn == 0) {
      if (on > 0) lo = INFINITY;
      continue;
    }
    double tc = -on / dn;
    if (dn < 0) lo = fmax(lo, tc);
    else hi = fmin(hi, tc);
  }
  *tin = lo;
  *tout = hi;
}

/* The closed convex mesh s around `center` with circumradius R: n rays of
 * each set. */
static inline int hr_watertight(const pb_scene *s, const char *name, const double center[3], double R, uint32_t n,
                                uint64_t seed, hr_trace_fn fn, void *user, hr_water_stats *st) {
  memset(st, 0, sizeof *st);
  uint32_t nt = s->triangle_count, nv = s->vertex_count;
  double(*nrm)[3] = malloc(nt * sizeof *nrm); /* outward exact normals */
  /* Edge records (a, b, triangle): every edge twice, once per triangle, so
   * a record drawn uniformly is an edge drawn uniformly. */
  uint32_t ne = 3 * nt;
  uint32_t(*ed)[2] = malloc(ne * sizeof *ed);
  uint32_t *vcount = calloc(nv, sizeof *vcount), *vtri = malloc((size_t)nv * 16 * sizeof *vtri);
  pb_gpu_ray *rays = malloc(HR_BATCH * sizeof *rays);
  pb_gpu_hit *hits = malloc(HR_BATCH * sizeof *hits);
  double *expect = malloc(HR_BATCH * sizeof *expect);
  unsigned char *kind = malloc(HR_BATCH);
  if (!nrm || !ed || !vcount || !vtri || !rays || !hits || !expect || !kind) abort();
  for (uint32_t t = 0; t < nt; ++t) {
    hr_tri_normal(s, t, nrm[t]);
    double c[3];
    for (int k = 0; k < 3; ++k)
      c[k] = ((double)s->positions[s->triangles[t][0]][k] + s->positions[s->triangles[t][1]][k] +
              s->positions[s->triangles[t][2]][k]) / 3.0 - center[k];
    if (hr_dot(c, nrm[t]) <= 0) {
      fprintf(stderr, "%s: triangle %u faces inward\n", name, t);
      abort();
    }
    for (int e = 0; e < 3; ++e) {
      ed[3 * t + (uint32_t)e][0] = s->triangles[t][e];
      ed[3 * t + (uint32_t)e][1] = s->triangles[t][(e + 1) % 3];
      uint32_t v = s->triangles[t][e];
      if (vcount[v] >= 16) abort();
      vtri[v * 16 + vcount[v]++] = t;
    }
  }
  double amax = 0; /* largest coordinate magnitude */
  for (uint32_t i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) amax = fmax(amax, fabs(s->positions[i][k]));
  for (int k = 0; k < 3; ++k) amax = fmax(amax, fabs(center[k]) + 2 * R);
  /* t tolerance: rounding of origins and directions (a few float ulps of
   * the coordinates), the t of a hit computed in float, and 1e-5 R. */
  const double tol = 1e-5 * R + 64 * amax * 1.2e-7;
  const size_t ns = sizeof hr_edge_s / sizeof *hr_edge_s;
  uint64_t rs = seed;
  int ok = 1;
  for (int set = 0; set < HR_SETS && ok; ++set) {
    for (uint32_t base = 0; base < n && ok; base += HR_BATCH) {
      uint32_t m = n - base < HR_BATCH ? n - base : HR_BATCH;
      for (uint32_t i = 0; i < m; ++i) {
        /* Target: a point on a random edge, a at the nearer end. */
        const uint32_t *e = ed[(uint32_t)(hr_rand(&rs) * ne) % ne];
        int flip = hr_rand(&rs) < 0.5;
        uint32_t a = e[flip], b = e[!flip];
        double sp = hr_edge_s[(size_t)(hr_rand(&rs) * ns) % ns];
        if (sp < 0) sp = 0.5 * hr_rand(&rs);
        kind[i] = sp == 0.0 ? HR_VERTEX : sp <= 1e-5 ? HR_NEAR_VERTEX : HR_EDGE;
        double x[3];
        for (int k = 0; k < 3; ++k)
          x[k] = (double)s->positions[a][k] + sp * ((double)s->positions[b][k] - s->positions[a][k]);
        /* Faces that touch x or lie close: the fan of a near the vertex,
         * the two triangles of the edge otherwise. */
        uint32_t faces[16], nf = 0;
        for (uint32_t j = 0; j < vcount[a]; ++j) {
          uint32_t t = vtri[a * 16 + j];
          int has_b = 0;
          for (int q = 0; q < 3; ++q) has_b |= s->triangles[t][q] == b;
          if (sp <= 1e-3 || has_b) faces[nf++] = t;
        }
        double d[3], o[3];
        if (set == HR_OUT) {
          /* A direction entering the solid at x through every face there,
           * by a margin (not grazing); from 2R away. */
          for (int tries = 0;; ++tries) {
            hr_sphere(&rs, d);
            int good = 1;
            for (uint32_t j = 0; j < nf && good; ++j) good = hr_dot(d, nrm[faces[j]]) < -0.1;
            if (good) break;
            if (tries > 100000) abort();
          }
          for (int k = 0; k < 3; ++k) o[k] = x[k] - 2.0 * R * d[k];
          expect[i] = 2.0 * R;
        } else {
          /* From a random point of the ball of radius R / 2 inside. */
          double q[3];
          do {
            for (int k = 0; k < 3; ++k) q[k] = 2 * hr_rand(&rs) - 1;
          } while (hr_dot(q, q) > 1);
          for (int k = 0; k < 3; ++k) o[k] = center[k] + 0.5 * R * q[k];
          if (set == HR_IN) {
            for (int k = 0; k < 3; ++k) d[k] = x[k] - o[k];
            expect[i] = sqrt(hr_dot(d, d));
          } else {
            hr_sphere(&rs, d);
            expect[i] = -1; /* any exit */
            kind[i] = HR_EDGE; /* counted as one class */
          }
        }
        hr_ray(&rays[i], o, d);
      }
      if (!hr_trace_all(fn, user, rays, m, hits)) {
        ok = 0;
        break;
      }
      for (uint32_t i = 0; i < m; ++i) {
        const pb_gpu_hit *h = &hits[i];
        int hit = h->prim != PB_GPU_MISS && h->prim < nt;
        if (h->prim != PB_GPU_MISS && !hr_hit_finite(h)) {
          st->nonfinite++;
          hit = 0;
        }
        /* Quick judgement: the first hit is on the face it crosses (entry
         * from outside, exit from inside) at the expected distance. */
        int good = 0;
        if (hit) {
          double df[3] = {rays[i].dir[0], rays[i].dir[1], rays[i].dir[2]};
          double c = hr_dot(df, nrm[h->prim]);
          good = (set == HR_OUT ? c < 0 : c > 0) && (expect[i] < 0 || fabs(h->t - expect[i]) <= tol);
        }
        if (!good) {
          /* The exact answer for the float ray decides. */
          double tin, tout;
          hr_interval(s, (const double(*)[3])nrm, &rays[i], &tin, &tout);
          if (set == HR_OUT && !(tout - tin > 1e-4 * R)) {
            st->ill_posed++;
            continue;
          }
          double te = set == HR_OUT ? tin : tout;
          good = hit && fabs(h->t - te) <= tol;
        }
        st->rays[set][kind[i]]++;
        if (!good) {
          uint64_t all = 0;
          for (int k = 0; k < HR_KINDS; ++k) all += st->misses[set][k];
          st->misses[set][kind[i]]++;
          if (all < 3)
            fprintf(stderr, "%s: %s %s miss: org (%.9g %.9g %.9g) dir (%.9g %.9g %.9g): prim %d t %.9g, expected t %.9g\n",
                    name, hr_set_name[set], hr_kind_name[kind[i]], rays[i].org[0], rays[i].org[1], rays[i].org[2],
                    rays[i].dir[0], rays[i].dir[1], rays[i].dir[2], (int)h->prim, h->t, expect[i]);
        }
      }
    }
  }
  free(nrm);
  free(ed);
  free(vcount);
  free(vtri);
  free(rays);
  free(hits);
  free(expect);
  free(kind);
  return ok;
}

static inline uint64_t hr_sum_rays(const hr_water_stats *st, int set, int kind) {
  uint64_t r = 0;
  for (int s = 0; s < HR_SETS; ++s)
    for (int k = 0; k < HR_KINDS; ++k)
      if ((set < 0 || s == set) && (kind < 0 || k == kind)) r += st->rays[s][k];
  return r;
}

static inline uint64_t hr_sum_misses(const hr_water_stats *st, int set, int kind) {
  uint64_t r = 0;
  for (int s = 0; s < HR_SETS; ++s)
    for (int k = 0; k < HR_KINDS; ++k)
      if ((set < 0 || s == set) && (kind < 0 || k == kind)) r += st->misses[s][k];
  return r;
}

static inline void hr_water_add(hr_water_stats *sum, const hr_water_stats *st) {
  for (int s = 0; s < HR_SETS; ++s)
    for (int k = 0; k < HR_KINDS; ++k) {
      sum->rays[s][k] += st->rays[s][k];
      sum->misses[s][k] += st->misses[s][k];
    }
  sum->ill_posed += st->ill_posed;
  sum->nonfinite += st->nonfinite;
}

static inline void hr_water_print(const char *who, const char *name, const hr_water_stats *st) {
  printf("%s %-22s watertight:", who, name);
  for (int s = 0; s < HR_SETS; ++s)
    for (int k = 0; k < HR_KINDS; ++k) {
      if (s == HR_RANDOM && k != HR_EDGE) continue;
      printf(" %s%s%s %llu/%llu", hr_set_name[s], s == HR_RANDOM ? "" : " ", s == HR_RANDOM ? "" : hr_kind_name[k],
             (unsigned long long)st->misses[s][k], (unsigned long long)st->rays[s][k]);
      printf(s == HR_RANDOM ? ";" : ",");
    }
  printf(" ill-posed %llu; non-finite %llu\n", (unsigned long long)st->ill_posed, (unsigned long long)st->nonfinite);
}

/* Asserts (pbtest.h's CHECK: include it first) at most `bound` misses in
 * every class of rays, `vertex_bound` for rays through and near vertices;
 * prints each class's fraction. */
static inline void hr_water_check(const char *who, const hr_water_stats *st, double vertex_bound) {
  const double bound = 2e-5;
  for (int s = 0; s < HR_SETS; ++s)
    for (int k = 0; k < HR_KINDS; ++k) {
      if (s == HR_RANDOM && k != HR_EDGE) continue;
      double b = k == HR_EDGE ? bound : vertex_bound;
      uint64_t n = st->rays[s][k], m = st->misses[s][k];
      printf("%s watertight %s%s%s: %llu rays, %llu misses, fraction %.2g (bound %.0e)\n", who, hr_set_name[s],
             s == HR_RANDOM ? "" : " ", s == HR_RANDOM ? "" : hr_kind_name[k], (unsigned long long)n,
             (unsigned long long)m, n ? (double)m / (double)n : 0.0, b);
      CHECK(n > 0);
      CHECK((double)m <= b * (double)n);
    }
  uint64_t out = hr_sum_rays(st, HR_OUT, -1);
  CHECK(st->ill_posed <= out / 100);
  CHECK_EQ_INT(st->nonfinite, 0);
}

/* ---- the scene list ------------------------------------------------------ */

/* Self-intersection scenes: the two samples and four soups. */
typedef struct hr_scene_def {
  const char *name;
  const char *sample;  /* samples/NAME/NAME.gltf, or NULL for a soup */
  double scale, size, center[3];
} hr_scene_def;

static const hr_scene_def hr_self_scenes[] = {
    {"sun_atrium", "sun_atrium", 0, 0, {0, 0, 0}},
    {"ring", "ring", 0, 0, {0, 0, 0}},
    {"soup 1e-3 @0", NULL, 1e-3, 0.05, {0, 0, 0}},
    {"soup 1 @0", NULL, 1, 0.05, {0, 0, 0}},
    {"soup 1e3 @0", NULL, 1e3, 0.05, {0, 0, 0}},
    {"soup 100 @1e4", NULL, 100, 0.05, {1e4, -1e4, 1e4}},
    /* Triangles up to 1000 across, all around the origin, so that hit
     * points have coordinates much smaller than the triangles' vertices.
     * pb_offset_ray moves by 256 ulps of the point's own coordinates, while
     * the intersectors' plane distance errs in proportion to the triangle
     * (pbrt-v4 bounds the point's error by gamma(7) sum |b_i p_i| instead):
     * about 4 rays in 10^3 re-hit their own triangle on Embree and 1 in 10^2
     * on the GPU kernel, until the side tests were made exact (Embree filter
     * in src/ref/accel.c) and conservative (shaders/common/bvh.glsl). */
    {"big 1e-2 x 1e3 @0", NULL, 1e-2, 1e5, {0, 0, 0}},
};

/* Watertight meshes: icosphere (level 4, 5120 triangles) and cube, each at
 * scales 1e-3, 1, 1e3 around the origin and at scale 1 around 1e4. */
typedef struct hr_mesh_def {
  const char *name;
  int ico;
  double scale, center[3];
} hr_mesh_def;

static const hr_mesh_def hr_meshes[] = {
    {"icosphere 1e-3 @0", 1, 1e-3, {0, 0, 0}}, {"icosphere 1 @0", 1, 1, {0, 0, 0}},
    {"icosphere 1e3 @0", 1, 1e3, {0, 0, 0}},   {"icosphere 1 @1e4", 1, 1, {1e4, 1e4, -1e4}},
    {"cube 1e-3 @0", 0, 1e-3, {0, 0, 0}},      {"cube 1 @0", 0, 1, {0, 0, 0}},
    {"cube 1e3 @0", 0, 1e3, {0, 0, 0}},        {"cube 1 @1e4", 0, 1, {1e4, 1e4, -1e4}},
};

/* Loads or builds self-intersection scene i. Returns 0 on failure. */
static inline int hr_self_scene(const hr_scene_def *d, uint64_t seed, pb_scene *s) {
  if (d->sample) {
    char path[256];
    snprintf(path, sizeof path, "samples/%s/%s.gltf", d->sample, d->sample);
    pb_load_desc ld = {0};
    return pb_scene_load(path, &ld, s) == PB_OK;
  }
  /* The big triangles overlap each other everywhere (no BVH helps): fewer. */
  hr_soup(s, seed, d->size > 1 ? 64 : 4000, d->scale, d->size, d->center);
  return 1;
}

static inline void hr_mesh(const hr_mesh_def *d, pb_scene *s, double *R) {
  if (d->ico) {
    hr_icosphere(s, 4, d->scale, d->center);
    *R = d->scale;
  } else {
    hr_cube(s, d->scale, d->center);
    *R = d->scale * sqrt(3.0);
  }
}

#endif
