/* The photon tracer (src/render/photon/photon_trace.c, shaders/photon/photon_trace.comp)
 * on small code-built scenes and cornell_caustics, photon buffer downloaded:
 *  (a) energy: closed Lambert box of albedo rho, point light inside: stored
 *      flux at bounce k is Phi rho^k (first hit never stored);
 *  (b) differentials against finite differences of traced neighbours
 *      (stencil triples): direct onto a plane, via a flat and a curved mirror
 *      (interpolated normals: Igehy's dN term), and after one diffuse
 *      re-emission (origin offset v, eq. 10-13);
 *  (c) determinism for a fixed seed/iteration, change for a new iteration;
 *  (d) no NaN/Inf, photons inside the scene bounds, unit normals/directions;
 *  (e) caustic flags: caustics only through mirror/glass (cornell_caustics,
 *      and none when its specular materials are made diffuse);
 *  (f) budget split over lights in proportion to power, equal photon flux;
 *  (g) hard cases: a 0.5-degree spot (every photon at the emission pole) and
 *      two parallel mirrors (long specular chains): records finite, every
 *      footprint within r_max.
 * Validation layers on, any message fatal; exit 77 without a device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "render/photon/photon.h"
#include "render/render.h"
#include "shared/pb_photon.h"

/* ---- code-built scenes --------------------------------------------------- */

#include "gpu_scene_helpers.h"

/* ---- tracing helpers ----------------------------------------------------- */

#include "photon_trace_helpers.h"

/* ---- (a) energy ------------------------------------------------------------ */

static void energy(pb_gpu *g) { check_box_energy(g, PB_FIRST_BOUNCE_TRACE, "energy"); }

/* ---- (b) differentials against finite differences ------------------------ */

/* Stencil triples (path 3 j + m): for records of triple j at bounce b,
 * compares the member displacements p_m - p_0 with (h / Delta) axis of
 * member 0 times `scale(j)` (1, or (t / (v + t)) after a re-emission).
 * Reports the median and 90th-percentile relative error. */
static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

static void fd_check(pb_gpu *g, const char *what, const pb_scene *s, uint32_t depth, uint32_t bounce,
                     int want_caustic, int reemit, double tol_median, double tol_p90) {
  const uint32_t triples = 4000;
  const float h = 2e-3f;
  pb_photon_trace_desc d = {.photons = 3 * triples, .max_bounces = 2};
  traced tr;
  if (!trace(g, s, &d, 11, 0, h, depth, PB_PHOTON_PARAM_RAW_FOOTPRINT | PB_PHOTON_PARAM_STORE_FIRST, &tr))
    return;
  /* index: [triple][member][bounce] -> record + 1 */
  uint32_t *idx = calloc((size_t)triples * 3 * 4, sizeof *idx);
  for (uint32_t i = 0; i < tr.n; ++i) {
    uint32_t b = bounce_of(&tr.ph[i]), p = tr.ph[i].path;
    if (b < 4 && p < 3 * triples) idx[(size_t)p * 4 + b] = i + 1;
  }
  double *err = calloc((size_t)triples * 2, sizeof *err);
  uint32_t ne = 0;
  double delta = tr.st.delta;
  for (uint32_t j = 0; j < triples; ++j) {
    uint32_t i0 = idx[(size_t)(3 * j) * 4 + bounce];
    if (!i0) continue;
    const pb_gpu_photon *p0 = &tr.ph[i0 - 1];
    if (((p0->flags & PB_PHOTON_CAUSTIC) != 0) != want_caustic && bounce > 0) continue;
    double scale = 1.0;
    if (reemit) {
      /* the re-emission point: bounce - 1 of member 0 */
      uint32_t ip = idx[(size_t)(3 * j) * 4 + bounce - 1];
      if (!ip) continue;
      const pb_gpu_photon *q = &tr.ph[ip - 1];
      double cx = (double)q->axis_u[1] * q->axis_v[2] - (double)q->axis_u[2] * q->axis_v[1];
      double cy = (double)q->axis_u[2] * q->axis_v[0] - (double)q->axis_u[0] * q->axis_v[2];
      double cz = (double)q->axis_u[0] * q->axis_v[1] - (double)q->axis_u[1] * q->axis_v[0];
      double v = sqrt(sqrt(cx * cx + cy * cy + cz * cz)) / delta; /* eq. 13, raw axes = Delta dP */
      float dd[3] = {p0->position[0] - q->position[0], p0->position[1] - q->position[1],
                     p0->position[2] - q->position[2]};
      double tt = len3(dd);
      scale = tt / (v + tt);
    }
    for (uint32_t m = 1; m <= 2; ++m) {
      uint32_t im = idx[(size_t)(3 * j + m) * 4 + bounce];
      if (!im) continue;
      const pb_gpu_photon *pm = &tr.ph[im - 1];
      /* same surface only (a neighbour on another wall is no differential) */
      if (fabsf(pm->normal[0] - p0->normal[0]) + fabsf(pm->normal[1] - p0->normal[1]) +
              fabsf(pm->normal[2] - p0->normal[2]) > 1e-4f)
        continue;
      const float *ax = m == 1 ? p0->axis_u : p0->axis_v;
      double e2 = 0, l2 = 0;
      for (int c = 0; c < 3; ++c) {
        double pred = (double)h / delta * ax[c] * scale;
        double got = (double)pm->position[c] - p0->position[c];
        e2 += (got - pred) * (got - pred);
        l2 += pred * pred;
      }
      if (l2 > 0) err[ne++] = sqrt(e2 / l2);
    }
  }
  qsort(err, ne, sizeof *err, cmp_double);
  double med = ne ? err[ne / 2] : 1e9, p90 = ne ? err[(ne * 9) / 10] : 1e9;
  printf("differentials, %s: %u neighbour pairs, relative error of Delta dP vs finite differences: median "
         "%.2e, 90th percentile %.2e (thresholds %.0e, %.0e)\n",
         what, ne, med, p90, tol_median, tol_p90);
  CHECK(ne > triples / 4);
  CHECK(med < tol_median);
  CHECK(p90 < tol_p90);
  free(err);
  free(idx);
  release(g, &tr);
}

static void differentials(pb_gpu *g) {
  static tscene a, b;
  float w[3] = {1, 1, 1};
  /* Two white Lambert planes 2 m apart, light between them. */
  memset(&a, 0, sizeof a);
  uint32_t m = add_mat(&a, 1.0f, 0);
  add_hplane(&a, 0, 30, 1, m);
  add_hplane(&a, 2, 30, 0, m);
  add_point(&a, 0, 0.7f, 0, 1, w);
  finish(&a);
  fd_check(g, "point light onto a plane", &a.s, 0, 0, 1, 0, 0.01, 0.05);
  fd_check(g, "after one diffuse re-emission", &a.s, 1, 1, 0, 1, 0.01, 0.05);
  /* Lambert floor, mirror ceiling. */
  memset(&b, 0, sizeof b);
  uint32_t mf = add_mat(&b, 1.0f, 0), mm = add_mat(&b, 1.0f, 1.0f);
  add_hplane(&b, 0, 30, 1, mf);
  add_hplane(&b, 2, 30, 0, mm);
  add_point(&b, 0, 0.7f, 0, 1, w);
  finish(&b);
  fd_check(g, "via a mirror", &b.s, 0, 1, 1, 0, 0.01, 0.05);
  /* The same mirror curved: its four vertex normals tilt outwards, so the
   * interpolated shading normal turns across it like a concave mirror's
   * (Igehy's dN term; without it the footprints after the mirror are off by
   * the normal's derivative). */
  static tscene c;
  memset(&c, 0, sizeof c);
  mf = add_mat(&c, 1.0f, 0), mm = add_mat(&c, 1.0f, 1.0f);
  add_hplane(&c, 0, 30, 1, mf);
  uint32_t first = c.nv;
  add_hplane(&c, 2, 30, 0, mm);
  for (uint32_t i = first; i < c.nv; ++i) {
    float n[3] = {-0.02f * c.pos[i][0], -1.0f, -0.02f * c.pos[i][2]};
    float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k) c.nrm[i][k] = n[k] / l;
  }
  add_point(&c, 0, 0.7f, 0, 1, w);
  finish(&c);
  fd_check(g, "via a curved mirror (interpolated normals)", &c.s, 0, 1, 1, 0, 0.01, 0.05);
  /* A curved glass interface (ior 1.5, the same tilted normals) between the
   * light above and the floor: Igehy's refraction with dN. */
  static tscene e;
  memset(&e, 0, sizeof e);
  mf = add_mat(&e, 1.0f, 0);
  uint32_t mg = add_mat(&e, 1.0f, 0);
  e.mat[mg].transmission = 1;
  e.mat[mg].roughness = 0;
  e.mat[mg].ior = 1.5f;
  e.mat[mg].specular = 1;
  e.mat[mg].specular_color[0] = e.mat[mg].specular_color[1] = e.mat[mg].specular_color[2] = 1;
  add_hplane(&e, 0, 30, 1, mf);
  first = e.nv;
  add_hplane(&e, 1, 30, 1, mg);
  for (uint32_t i = first; i < e.nv; ++i) {
    float n[3] = {0.02f * e.pos[i][0], 1.0f, 0.02f * e.pos[i][2]};
    float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; ++k) e.nrm[i][k] = n[k] / l;
  }
  add_point(&e, 0, 1.7f, 0, 1, w);
  finish(&e);
  fd_check(g, "through a curved glass interface", &e.s, 0, 1, 1, 0, 0.01, 0.05);
}

/* ---- (c) determinism, (d) records ----------------------------------------- */

static void determinism(pb_gpu *g) {
  static tscene t;
  box(&t, 0.7f);
  float w[3] = {1, 1, 1};
  add_point(&t, 0.2f, 0.1f, -0.3f, 1, w);
  finish(&t);
  pb_photon_trace_desc d = {.photons = 4096, .max_bounces = 3};
  traced a, b, c;
  if (!trace(g, &t.s, &d, 5, 3, 0, 0, 0, &a)) return;
  if (!trace(g, &t.s, &d, 5, 3, 0, 0, 0, &b)) return;
  if (!trace(g, &t.s, &d, 5, 4, 0, 0, 0, &c)) return;
  /* Record order depends on atomics: compare per (path, bounce). */
  uint32_t n = 4096 * 4;
  pb_gpu_photon *sa = calloc(n, sizeof *sa), *sb = calloc(n, sizeof *sb), *sc = calloc(n, sizeof *sc);
  const traced *tt[3] = {&a, &b, &c};
  pb_gpu_photon *ss[3] = {sa, sb, sc};
  for (int k = 0; k < 3; ++k)
    for (uint32_t i = 0; i < tt[k]->n; ++i) {
      const pb_gpu_photon *p = &tt[k]->ph[i];
      uint32_t slot = p->path * 4 + bounce_of(p);
      if (slot < n) ss[k][slot] = *p;
    }
  CHECK_EQ_INT(a.n, b.n);
  CHECK(memcmp(sa, sb, n * sizeof *sa) == 0);
  CHECK(a.n != c.n || memcmp(sa, sc, n * sizeof *sa) != 0);
  uint32_t same = 0;
  for (uint32_t i = 0; i < n; ++i)
    if (sa[i].power[0] > 0 && memcmp(&sa[i], &sc[i], sizeof *sa) == 0) same++;
  printf("determinism: %u records twice identical; new iteration: %u records, %u identical\n", a.n, c.n, same);
  CHECK(same < a.n / 100 + 1);
  check_records(&t.s, &a, "determinism box");
  free(sa);
  free(sb);
  free(sc);
  release(g, &a);
  release(g, &b);
  release(g, &c);
}

/* ---- seed 003's variable bandwidth (--bandwidth-c0) ------------------------- */

/* The same paths as the differential footprints (the bandwidth changes no
 * path: same records per (path, bounce), same positions and powers), every
 * footprint an isotropic disc in the tangent plane, and its radius eq.
 * h = C0 / sqrt(clamp(cos(theta) R^2 / d^2, 1/4, 4)) sqrt(A / N) (photon.h):
 * d taken from the path's previous stored record (a diffuse box: every
 * segment after the first bounce runs between two stored records). */
static void bandwidth(pb_gpu *g) {
  static tscene t;
  box(&t, 0.7f);
  float w[3] = {1, 1, 1};
  add_point(&t, 0.2f, 0.1f, -0.3f, 1, w);
  finish(&t);
  const uint32_t N = 16384, B = 3;
  const float c0 = 2.0f;
  pb_photon_trace_desc d = {.photons = N, .max_bounces = B};
  pb_photon_trace_desc dbw = d;
  dbw.bandwidth_c0 = c0;
  traced a, b;
  if (!trace(g, &t.s, &d, 9, 0, 0, 0, 0, &a)) return;
  if (!trace(g, &t.s, &dbw, 9, 0, 0, 0, 0, &b)) return;
  uint32_t n = N * (B + 1);
  pb_gpu_photon *sa = calloc(n, sizeof *sa), *sb = calloc(n, sizeof *sb);
  for (uint32_t i = 0; i < a.n; ++i)
    if (a.ph[i].path * (B + 1) + bounce_of(&a.ph[i]) < n) sa[a.ph[i].path * (B + 1) + bounce_of(&a.ph[i])] = a.ph[i];
  for (uint32_t i = 0; i < b.n; ++i)
    if (b.ph[i].path * (B + 1) + bounce_of(&b.ph[i]) < n) sb[b.ph[i].path * (B + 1) + bounce_of(&b.ph[i])] = b.ph[i];
  const double R = sqrt(3.0), A = 24.0, h0 = c0 * sqrt(A / N); /* the [-1, 1]^3 box */
  uint32_t moved = 0, aniso = 0, out_of_range = 0, checked = 0, wrong = 0, clamped_p = 0;
  double worst = 0, sum_r = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const pb_gpu_photon *p = &sb[i], *q = &sa[i];
    if (!(q->power[0] > 0) && !(p->power[0] > 0)) continue;
    if (memcmp(p->position, q->position, sizeof p->position) || memcmp(p->power, q->power, sizeof p->power)) moved++;
    double lu = len3(p->axis_u), lv = len3(p->axis_v);
    double du = fabs(p->axis_u[0] * p->normal[0] + p->axis_u[1] * p->normal[1] + p->axis_u[2] * p->normal[2]);
    if (fabs(lu - lv) > 1e-4 * lu || fabs(lu - p->radius) > 1e-4 * lu || du > 1e-4 * lu) aniso++;
    if (!(p->radius >= 0.5 * h0 * 0.999 && p->radius <= 2.0 * h0 * 1.001)) out_of_range++;
    sum_r += p->radius;
    uint32_t bo = i % (B + 1);
    if (bo >= 2 && sb[i - 1].power[0] > 0) {
      const pb_gpu_photon *o = &sb[i - 1];
      double e[3] = {p->position[0] - o->position[0], p->position[1] - o->position[1], p->position[2] - o->position[2]};
      double dist2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
      double ct = fabs(p->wi[0] * p->normal[0] + p->wi[1] * p->normal[1] + p->wi[2] * p->normal[2]);
      double pr = ct * R * R / dist2;
      if (pr < 0.25 || pr > 4) clamped_p++;
      pr = pr < 0.25 ? 0.25 : (pr > 4 ? 4 : pr);
      double want = h0 / sqrt(pr), err = fabs(p->radius - want) / want;
      if (err > worst) worst = err;
      if (err > 0.01) wrong++;
      checked++;
    }
  }
  printf("bandwidth: C0 %.1f, h0 = C0 sqrt(A / N) = %.5f m; %u / %u records (bvh / bandwidth), %u moved, %u not "
         "isotropic discs, %u outside [h0/2, 2 h0], mean radius %.5f m; eq. checked on %u (%u at the p clamp): %u "
         "off by > 1 %%, worst %.3g\n",
         c0, h0, a.n, b.n, moved, aniso, out_of_range, b.n ? sum_r / b.n : 0.0, checked, clamped_p, wrong, worst);
  CHECK_EQ_INT(a.n, b.n);
  CHECK_EQ_INT(moved, 0);
  CHECK_EQ_INT(aniso, 0);
  CHECK_EQ_INT(out_of_range, 0);
  CHECK(checked > a.n / 4);
  CHECK_EQ_INT(wrong, 0);
  CHECK(clamped_p > 0 && clamped_p < checked); /* both regimes met */
  check_records(&t.s, &b, "bandwidth box");
  /* A negative C0 is refused. */
  dbw.bandwidth_c0 = -1.0f;
  pb_gpu_scene gs;
  if (pb_gpu_scene_create(g, &t.s, &gs) == PB_OK) {
    pb_photon_tracer *tr = NULL;
    CHECK_EQ_INT(pb_photon_tracer_create(g, &t.s, &gs, &dbw, &tr), PB_ERR_USAGE);
    pb_photon_tracer_destroy(g, tr);
    pb_gpu_scene_destroy(g, &gs);
  }
  free(sa);
  free(sb);
  release(g, &a);
  release(g, &b);
}

/* ---- (e) caustics ---------------------------------------------------------- */

static void caustics(pb_gpu *g) {
  pb_scene s;
  pb_load_desc ld = {0};
  pb_result r = pb_scene_load("samples/cornell_caustics/cornell_caustics.gltf", &ld, &s);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return;
  pb_photon_trace_desc d = {.photons = 30000, .max_bounces = 3};
  traced tr;
  if (trace(g, &s, &d, 3, 0, 0, 0, 0, &tr)) {
    /* A caustic photon's path has no earlier stored (smooth) hit, and its
     * bounce count is its specular chain length >= 1; non-caustic photons
     * exist too. */
    uint32_t bad = 0, nc = 0;
    uint8_t *has = calloc((size_t)30000 * 16, 1);
    for (uint32_t i = 0; i < tr.n; ++i) {
      uint32_t b = bounce_of(&tr.ph[i]);
      if (b < 16) has[(size_t)tr.ph[i].path * 16 + b] = 1;
    }
    for (uint32_t i = 0; i < tr.n; ++i) {
      const pb_gpu_photon *p = &tr.ph[i];
      if (!(p->flags & PB_PHOTON_CAUSTIC)) continue;
      nc++;
      uint32_t b = bounce_of(p);
      if (b < 1) bad++;
      for (uint32_t k = 0; k < b && k < 16; ++k)
        if (has[(size_t)p->path * 16 + k]) bad++;
    }
    printf("caustics: %u of %u photons caustic, %u inconsistent\n", nc, tr.n, bad);
    CHECK_EQ_INT(nc, tr.map.caustic);
    CHECK(nc > 0);
    CHECK(nc < tr.n);
    CHECK_EQ_INT(bad, 0);
    check_records(&s, &tr, "cornell_caustics");
    free(has);
    release(g, &tr);
  }
  /* The same scene with every material made Lambert: no caustics at all
   * (and the tracer compiles without specular code: SC_SPECULAR = 0). */
  for (uint32_t i = 0; i < s.material_count; ++i) {
    s.materials[i].metallic = 0;
    s.materials[i].transmission = 0;
    s.materials[i].roughness = 1;
  }
  pb_scene_finalize(&s);
  CHECK_EQ_INT(s.features & PB_FEATURE_SPECULAR, 0);
  if (trace(g, &s, &d, 3, 0, 0, 0, 0, &tr)) {
    printf("caustics, all diffuse: %u photons, %u caustic\n", tr.n, tr.map.caustic);
    CHECK_EQ_INT(tr.map.caustic, 0);
    CHECK(tr.n > 0);
    release(g, &tr);
  }
  pb_scene_destroy(&s);
}

/* ---- (f) budget split ----------------------------------------------------- */

static void budget(pb_gpu *g) {
  static tscene t;
  box(&t, 0.5f);
  float red[3] = {1, 0, 0}, green[3] = {0, 1, 0};
  add_point(&t, -0.5f, 0, 0, 1.0f / 0.2126f, red);   /* luminance 1 */
  add_point(&t, 0.5f, 0, 0, 3.0f / 0.7152f, green);  /* luminance 3 */
  finish(&t);
  uint32_t n[2], first[2];
  pb_photon_split_budget(&t.s, 40000, n, first);
  printf("budget: 40000 photons split %u / %u (power 1 : 3)\n", n[0], n[1]);
  CHECK_EQ_INT(n[0] + n[1], 40000);
  CHECK_EQ_INT(n[0], 10000);
  CHECK_EQ_INT(first[1], n[0]);
  /* Traced: first hits (stored for the test) by colour, and their flux. */
  pb_photon_trace_desc d = {.photons = 40000, .max_bounces = 1};
  traced tr;
  if (!trace(g, &t.s, &d, 9, 0, 0, 0, PB_PHOTON_PARAM_STORE_FIRST, &tr)) return;
  uint32_t cr = 0, cg = 0;
  double fr = 0, fg = 0;
  for (uint32_t i = 0; i < tr.n; ++i) {
    const pb_gpu_photon *p = &tr.ph[i];
    if (bounce_of(p) != 0) continue;
    if (p->power[0] > 0) cr++, fr = p->power[0];
    if (p->power[1] > 0) cg++, fg = p->power[1];
    CHECK(p->power[0] == 0 || p->path < first[1]);
  }
  printf("budget: first hits red %u, green %u; photon flux red %.6g, green %.6g (luminance-weighted %.6g, %.6g)\n",
         cr, cg, fr, fg, fr * 0.2126, fg * 0.7152);
  CHECK_EQ_INT(cr, 10000);
  CHECK_EQ_INT(cg, 30000);
  CHECK_NEAR(fr * 0.2126, fg * 0.7152, 1e-4 * fg);
  release(g, &tr);

  /* A spot and a directional light: split by pb_light_power too. */
  static tscene u;
  box(&u, 0.5f);
  float wcol[3] = {1, 1, 1};
  add_point(&u, 0, 0, 0, 1, wcol);
  pb_light *sp = &u.light[u.nl++];
  memset(sp, 0, sizeof *sp);
  sp->type = PB_LIGHT_SPOT;
  sp->position[1] = 0.5f;
  sp->direction[1] = -1;
  memcpy(sp->color, wcol, sizeof wcol);
  sp->intensity = 4;
  sp->inner_cone = 0.3f;
  sp->outer_cone = 0.6f;
  finish(&u);
  uint32_t n2[2], f2[2];
  pb_photon_split_budget(&u.s, 10000, n2, f2);
  float p0[3], p1[3];
  float r = 0.5f * sqrtf(12.0f);
  pb_light_power(&u.light[0], r, p0);
  pb_light_power(&u.light[1], r, p1);
  double want = 10000.0 * p1[1] / (p0[1] + p1[1]);
  printf("budget: point %u, spot %u (expected %.1f)\n", n2[0], n2[1], want);
  CHECK(fabs(n2[1] - want) <= 1.0);
  traced ts;
  pb_photon_trace_desc d2 = {.photons = 10000, .max_bounces = 3};
  if (trace(g, &u.s, &d2, 1, 0, 0, 0, 0, &ts)) {
    check_records(&u.s, &ts, "point + spot box");
    release(g, &ts);
  }
}

/* (d) on the sample scenes with spot and directional lights. */
static void samples(pb_gpu *g, const char *name) {
  char path[256];
  snprintf(path, sizeof path, "samples/%s/%s.gltf", name, name);
  pb_scene s;
  pb_load_desc ld = {0};
  pb_result r = pb_scene_load(path, &ld, &s);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return;
  pb_photon_trace_desc d = {.photons = 20000, .max_bounces = 3};
  traced tr;
  if (trace(g, &s, &d, 4, 1, 0, 0, 0, &tr)) {
    CHECK(tr.n > 0);
    CHECK_EQ_INT(tr.map.overflow, 0);
    check_records(&s, &tr, name);
    release(g, &tr);
  }
  pb_scene_destroy(&s);
}

/* Over-budget buffers are refused with a clear message. */
static void limits(pb_gpu *g) {
  static tscene t;
  box(&t, 0.5f);
  float w[3] = {1, 1, 1};
  add_point(&t, 0, 0, 0, 1, w);
  finish(&t);
  pb_gpu_scene gs;
  if (pb_gpu_scene_create(g, &t.s, &gs) != PB_OK) return;
  pb_photon_trace_desc d = {.photons = 2000000000u, .max_bounces = 8};
  pb_photon_tracer *tr = NULL;
  pb_result r = pb_photon_tracer_create(g, &t.s, &gs, &d, &tr);
  printf("limits: %s\n", pb_error_message());
  CHECK_EQ_INT(r, PB_ERR_LIMIT);
  CHECK(tr == NULL);
  pb_error_clear();
  pb_gpu_scene_destroy(g, &gs);

  /* A map larger than the device holds: every path of a closed white box
   * stores all of its bounces. The buffer is the largest one storage buffer
   * allows (or the worst case where that fits); what does not fit is
   * PB_ERR_LIMIT, never dropped photons. */
  uint64_t fit = pb_gpu_get_limits(g)->max_storage_buffer_range / sizeof(pb_gpu_photon);
  static tscene u;
  box(&u, 1.0f);
  add_point(&u, 0, 0, 0, 1, w);
  finish(&u);
  uint32_t paths = (uint32_t)(fit / 4 + 1000);
  if (fit < 0x7fffffffu && paths < 4000000u && pb_gpu_scene_create(g, &u.s, &gs) == PB_OK) {
    d = (pb_photon_trace_desc){.photons = paths, .max_bounces = 7};
    r = pb_photon_tracer_create(g, &u.s, &gs, &d, &tr);
    CHECK_EQ_INT(r, PB_OK);
    if (r == PB_OK) {
      pb_photon_map map;
      memset(&map, 0, sizeof map);
      r = pb_photon_tracer_run(g, tr, 1, 0, &map, NULL);
      printf("limits: %u paths x 7 bounces in a white box, %llu records fit: %s\n", paths,
             (unsigned long long)fit, r == PB_OK ? "fitted" : pb_error_message());
      CHECK_EQ_INT(r, PB_ERR_LIMIT);
      CHECK(strstr(pb_error_message(), "lower --photons") != NULL);
      pb_error_clear();
      pb_photon_map_destroy(g, &map);
    }
    pb_photon_tracer_destroy(g, tr);
    pb_gpu_scene_destroy(g, &gs);
  }
}

/* ---- (g) hard cases -------------------------------------------- */

/* Every record finite (check_records) and every footprint within the clamp. */
static void check_clamped(const pb_scene *s, const traced *t, const char *what) {
  check_records(s, t, what);
  uint32_t over = 0;
  float rmax = 0;
  for (uint32_t i = 0; i < t->n; ++i) {
    if (!(t->ph[i].radius <= t->st.r_max * (1 + 1e-5f))) over++;
    if (t->ph[i].radius > rmax) rmax = t->ph[i].radius;
  }
  printf("%s: largest footprint %.4g m, r_max %.4g m, %u over the clamp\n", what, rmax, t->st.r_max, over);
  CHECK(t->n > 0);
  CHECK_EQ_INT(over, 0);
}

static void hard_cases(pb_gpu *g) {
  /* A spot of 0.5 degree half-angle straight down in a closed box: every
   * photon leaves within 0.5 degree of the emission pole (sin theta -> 0 in
   * the (cos theta, phi) parameterisation, seed 000 eq. 6-8). */
  static tscene t;
  box(&t, 0.7f);
  float w[3] = {1, 1, 1};
  add_point(&t, 0, 0.99f, 0, 50.0f, w);
  t.light[0].type = PB_LIGHT_SPOT;
  t.light[0].direction[0] = 0, t.light[0].direction[1] = -1, t.light[0].direction[2] = 0;
  t.light[0].outer_cone = 0.5f * (float)M_PI / 180.0f;
  t.light[0].inner_cone = 0.25f * (float)M_PI / 180.0f;
  finish(&t);
  pb_photon_trace_desc d = {.photons = 1u << 16, .max_bounces = 3};
  traced tr;
  if (trace(g, &t.s, &d, 21, 0, 0, 0, PB_PHOTON_PARAM_STORE_FIRST, &tr)) {
    uint32_t first = 0;
    for (uint32_t i = 0; i < tr.n; ++i) first += bounce_of(&tr.ph[i]) == 0;
    CHECK(first > (1u << 15)); /* the pole's photons are really there */
    check_clamped(&t.s, &tr, "hard: spot of 0.5 deg at the emission pole");
    release(g, &tr);
  }

  /* Two parallel mirrors 1 m apart (x = +-0.5), 40 m long, over a diffuse
   * floor, a point light between them: photons leaving nearly along x bounce
   * between the mirrors up to the tracer's specular limit, their
   * differentials growing at every reflection. */
  memset(&t, 0, sizeof t);
  uint32_t mirror = add_mat(&t, 0.95f, 1.0f), floor_m = add_mat(&t, 0.5f, 0);
  float L = 20.0f;
  float left[4][3] = {{-0.5f, 0, -L}, {-0.5f, 0, L}, {-0.5f, 2, L}, {-0.5f, 2, -L}};
  float right[4][3] = {{0.5f, 0, -L}, {0.5f, 2, -L}, {0.5f, 2, L}, {0.5f, 0, L}};
  float nl[3] = {1, 0, 0}, nr[3] = {-1, 0, 0};
  add_quad(&t, left, nl, mirror);
  add_quad(&t, right, nr, mirror);
  float fl[4][3] = {{-0.5f, 0, -L}, {0.5f, 0, -L}, {0.5f, 0, L}, {-0.5f, 0, L}};
  float nf[3] = {0, 1, 0};
  add_quad(&t, fl, nf, floor_m);
  add_point(&t, 0.1f, 1.0f, 0, 10.0f, w);
  finish(&t);
  d = (pb_photon_trace_desc){.photons = 1u << 16, .max_bounces = 3};
  if (trace(g, &t.s, &d, 22, 0, 0, 0, 0, &tr)) {
    uint32_t deepest = 0;
    for (uint32_t i = 0; i < tr.n; ++i)
      if (bounce_of(&tr.ph[i]) > deepest) deepest = bounce_of(&tr.ph[i]);
    printf("hard: parallel mirrors: %u photons (%u caustic), deepest after %u interactions\n",
           tr.n, tr.map.caustic, deepest);
    CHECK(deepest >= 10);
    CHECK(tr.map.caustic > 0);
    check_clamped(&t.s, &tr, "hard: parallel mirrors");
    release(g, &tr);
  }
}

int main(void) {
  PBT_GPU_OPEN(g);
  energy(g);
  differentials(g);
  determinism(g);
  bandwidth(g);
  caustics(g);
  budget(g);
  samples(g, "spot_room");
  samples(g, "sun_atrium");
  samples(g, "ring");
  limits(g);
  hard_cases(g);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
