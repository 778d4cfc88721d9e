/* The RSM first bounce (src/render/photon/photon_rsm.c, shaders/photon/photon_rsm.comp,
 * pb_photon_trace_desc.first_bounce = PB_FIRST_BOUNCE_RSM) against the traced
 * first bounce:
 *  (a) energy: closed Lambert box of albedo rho, point light inside: stored
 *      flux at bounce k is Phi rho^k; a spot in the box matches the traced
 *      spot per bounce (falloff and cone);
 *  (b) the same stored-flux distribution as the traced path: totals per
 *      bounce and per wall (normal direction) on cornell_box, and per bounce
 *      on sun_atrium (directional light) and spot_room;
 *  (c) no NaN/Inf in any record;
 *  (d) photons jittered over their texel: distinct first hits, and the exact
 *      first-hit flux on a plate whose edges cut texels;
 *  (e) ring: the same caustic flux traced and from the map, the map's
 *      caustic records 1 / coverage times the traced ones (the caustic share
 *      off), and PB_FIRST_BOUNCE_AUTO choosing the map there and tracing
 *      cornell_box; with the default caustic share (0.5: the mirror texels
 *      weighted up to half of the map's photons) the same caustic flux again
 *      from over 4x the records;
 * Validation layers on, any message fatal; exit 77 without a device. */
#include <math.h>
#include <stdio.h>
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

/* Stored flux per bounce (1..7) and per bounce-1 normal bin (6 axis
 * directions), luminance-free (sum of the three channels). */
typedef struct dist {
  double bounce[8], wall[6], total, area1; /* area1: mean pi a b of bounce-1 footprints */
  uint32_t bad, n1;
} dist;

static void tally(const traced *t, dist *d) {
  memset(d, 0, sizeof *d);
  for (uint32_t i = 0; i < t->n; ++i) {
    const pb_gpu_photon *p = &t->ph[i];
    if (!finite3(p->position) || !finite3(p->power) || !finite3(p->axis_u) || !finite3(p->axis_v) ||
        !finite3(p->normal) || !finite3(p->wi) || !isfinite(p->radius) || !isfinite(p->normal_extent) ||
        !(p->radius > 0)) {
      d->bad++;
      continue;
    }
    double f = (double)p->power[0] + p->power[1] + p->power[2];
    uint32_t b = bounce_of(p);
    if (b < 8) d->bounce[b] += f;
    if (b == 1) d->area1 += M_PI * (double)p->radius * p->normal_extent, d->n1++;
    d->total += f;
    int ax = 0;
    for (int c = 1; c < 3; ++c)
      if (fabs(p->normal[c]) > fabs(p->normal[ax])) ax = c;
    d->wall[2 * ax + (p->normal[ax] < 0)] += f;
  }
}

static void compare(const char *what, const dist *tr, const dist *rs, double tol, int walls) {
  /* Differentials: footprints of the first stored bounce (after one diffuse
   * re-emission, so the texel's footprint / sqrt(n p_i) reached it). */
  double at = tr->n1 ? tr->area1 / tr->n1 : 0, ar = rs->n1 ? rs->area1 / rs->n1 : 0;
  printf("%s: bounce-1 mean footprint area: traced %.4g m^2, RSM %.4g m^2 (%+.1f %%)\n", what, at, ar,
         100 * (ar / at - 1));
  CHECK_NEAR(ar, at, 0.25 * at);
  for (int k = 1; k < 8; ++k) {
    if (tr->bounce[k] < 0.03 * tr->total) continue;
    printf("%s: bounce %d: traced %.5f W, RSM %.5f W (%+.2f %%)\n", what, k, tr->bounce[k], rs->bounce[k],
           100 * (rs->bounce[k] / tr->bounce[k] - 1));
    CHECK_NEAR(rs->bounce[k], tr->bounce[k], tol * tr->bounce[k]);
  }
  if (!walls) return;
  static const char *name[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};
  for (int w = 0; w < 6; ++w) {
    if (tr->wall[w] < 0.05 * tr->total) continue;
    printf("%s: normal %s: traced %.5f W, RSM %.5f W (%+.2f %%)\n", what, name[w], tr->wall[w], rs->wall[w],
           100 * (rs->wall[w] / tr->wall[w] - 1));
    CHECK_NEAR(rs->wall[w], tr->wall[w], tol * tr->wall[w]);
  }
}

/* Traces s with both first bounces, checks records and compares. */
static void both(pb_gpu *g, const pb_scene *s, const char *what, uint32_t photons, uint32_t bounces, double tol,
                 int walls) {
  pb_photon_trace_desc dt = {.photons = photons, .max_bounces = bounces, .first_bounce = PB_FIRST_BOUNCE_TRACE};
  pb_photon_trace_desc dr = dt;
  dr.first_bounce = PB_FIRST_BOUNCE_RSM;
  traced a, b;
  if (!trace(g, s, &dt, 11, 0, 0, 0, 0, &a)) return;
  if (!trace(g, s, &dr, 11, 0, 0, 0, 0, &b)) {
    release(g, &a);
    return;
  }
  dist da, db;
  tally(&a, &da);
  tally(&b, &db);
  printf("%s: traced %u records, RSM %u records (%u non-finite), RSM guarded %u\n", what, a.n, b.n, db.bad,
         b.st.guarded);
  CHECK_EQ_INT(db.bad, 0);
  CHECK_EQ_INT(b.map.overflow, 0);
  CHECK(b.n > 0);
  compare(what, &da, &db, tol, walls);
  release(g, &a);
  release(g, &b);
}

/* ---- (a) energy ------------------------------------------------------------ */

static void energy(pb_gpu *g) {
  check_box_energy(g, PB_FIRST_BOUNCE_RSM, "rsm energy");
  const float rho = 0.6f;

  /* A spot in the box: falloff and cone against the traced spot. */
  static tscene u;
  box(&u, rho);
  pb_light *l = &u.light[u.nl++];
  memset(l, 0, sizeof *l);
  l->type = PB_LIGHT_SPOT;
  l->position[1] = 0.5f;
  l->direction[0] = 0.3f, l->direction[1] = -1.0f, l->direction[2] = 0.1f;
  l->color[0] = l->color[1] = l->color[2] = 1;
  l->intensity = 3;
  l->inner_cone = 0.3f;
  l->outer_cone = 0.7f;
  finish(&u);
  both(g, &u.s, "rsm spot box", 40000, 3, 0.04, 1);
}

/* ---- (b) distributions on the samples ------------------------------------ */

static void sample(pb_gpu *g, const char *name, uint32_t photons, int walls) {
  char path[256];
  snprintf(path, sizeof path, "samples/%s/%s.gltf", name, name);
  pb_scene s;
  pb_load_desc ld = {0};
  pb_result r = pb_scene_load(path, &ld, &s);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return;
  both(g, &s, name, photons, 3, 0.05, walls);
  pb_scene_destroy(&s);
}

/* ---- (e) ring: where the RSM's extra caustic records come from ------------ */

typedef struct caustics {
  uint32_t n;               /* caustic records */
  double flux, other, all;  /* caustic flux, the rest's, all (sum of channels) */
} caustics;

static caustics caustic_tally(const traced *t) {
  caustics c = {0};
  for (uint32_t i = 0; i < t->n; ++i) {
    const pb_gpu_photon *p = &t->ph[i];
    double f = (double)p->power[0] + p->power[1] + p->power[2];
    c.all += f;
    if (p->flags & PB_PHOTON_CAUSTIC) c.n++, c.flux += f;
    else c.other += f;
  }
  return c;
}

/* ring (point light 3 m from a 4 x 4 m floor and a 1 m metal ring): at
 * equal paths and equal emitted power the RSM stored some 22x the traced
 * first bounce's caustic records (bench/README.md). Both carry the same
 * caustic flux (within the traced map's noise), so the records are not
 * flagged or weighted differently; the ratio of their counts is the map's
 * gain 1 / coverage: the traced emission sends only the share of the
 * light's sphere the scene covers onto it, the floor's 0.618 sr (4.9 %,
 * integrated over the 4 x 4 m square at 0.65 m below the light, 1 .. 5 m
 * away) and the ring's under 0.05 sr, while the map spends every photon on
 * the scene, by reflected power (albedo 0.8 floor, 0.96 ring): the ring's
 * share of the map's photons over its share of the sphere is
 * 0.96 x 4 pi / (0.8 x 0.618 + 0.96 Omega_ring) = 22.2 .. 24.4 for
 * Omega_ring in 0 .. 0.05 sr. --first-bounce auto picks the map here
 * (coverage about 0.05 < 0.5: the same records as RSM) and the traced first
 * bounce on cornell_box (a closed room but for its front: the same records
 * as traced). The caustic share (photon_rsm.comp PB_RSM_MODE_BOOST) is off
 * for these counts (caustic_share < 0); with the default 0.5 the ring's
 * texels, about 9 % of the map's reflected power, get half of its photons:
 * some 5.6x the caustic records (0.5 / 0.089), each carrying as much less
 * flux, so the caustic flux stays the traced one's (unbiased for any
 * positive texel weights). */
static void ring(pb_gpu *g) {
  pb_scene s;
  pb_load_desc ld = {0};
  pb_result r = pb_scene_load("samples/ring/ring.gltf", &ld, &s);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return;
  pb_photon_trace_desc dt = {.photons = 1u << 19, .max_bounces = 3, .first_bounce = PB_FIRST_BOUNCE_TRACE};
  pb_photon_trace_desc dr = dt, da = dt;
  dr.first_bounce = PB_FIRST_BOUNCE_RSM;
  da.first_bounce = PB_FIRST_BOUNCE_AUTO;
  dr.caustic_share = da.caustic_share = -1.0f; /* by reflected power alone */
  pb_photon_trace_desc ds = dr;
  ds.caustic_share = 0.0f; /* the default share */
  traced a, b, c, e;
  memset(&a, 0, sizeof a), memset(&b, 0, sizeof b), memset(&c, 0, sizeof c); /* released whatever failed */
  memset(&e, 0, sizeof e);
  int ok = trace(g, &s, &dt, 21, 0, 0, 0, 0, &a);
  ok = ok && trace(g, &s, &dr, 21, 0, 0, 0, 0, &b);
  ok = ok && trace(g, &s, &da, 21, 0, 0, 0, 0, &c);
  ok = ok && trace(g, &s, &ds, 21, 0, 0, 0, 0, &e);
  if (ok) {
    caustics ct = caustic_tally(&a), cr = caustic_tally(&b), ca = caustic_tally(&c), ce = caustic_tally(&e);
    printf("ring: RSM with the caustic share (specular texels x %.3g): %u caustic records (%.2f x the share "
           "off), caustic flux %.5f W (%+.2f %% against traced)\n", e.st.rsm_boost, ce.n,
           cr.n ? (double)ce.n / cr.n : 0.0, ce.flux, 100 * (ce.flux / ct.flux - 1));
    CHECK(e.st.rsm_boost > 4);
    CHECK(ce.n > 4 * cr.n);
    CHECK_NEAR(ce.flux, ct.flux, 0.08 * ct.flux);
    CHECK_NEAR(ce.flux, cr.flux, 0.03 * cr.flux);
    check_records(&s, &e, "ring RSM caustic share");
    double ratio = ct.n ? (double)cr.n / ct.n : 0;
    printf("ring: traced %u records, %u caustic, caustic flux %.5f W, other %.5f W, %u escaped\n", a.n, ct.n,
           ct.flux, ct.other, a.st.escaped);
    printf("ring: RSM    %u records, %u caustic, caustic flux %.5f W (%+.2f %%), other %.5f W, %u escaped\n", b.n,
           cr.n, cr.flux, 100 * (cr.flux / ct.flux - 1), cr.other, b.st.escaped);
    printf("ring: caustic records RSM / traced %.2f (predicted 22.2 .. 24.4); map coverage %.4f; auto: %u "
           "caustic of %u, %u lights from their map\n", ratio, b.st.rsm_coverage, ca.n, c.n, c.st.rsm_lights);
    CHECK(b.st.rsm_coverage > 0.03 && b.st.rsm_coverage < 0.08);
    CHECK_EQ_INT(c.st.rsm_lights, 1);
    CHECK(ct.n > 500);
    CHECK_NEAR(cr.flux, ct.flux, 0.08 * ct.flux);
    CHECK(ratio > 18 && ratio < 29);
    CHECK_EQ_INT(ca.n, cr.n);
    CHECK_EQ_INT(c.n, b.n);
    check_records(&s, &b, "ring RSM");
  }
  release(g, &e);
  release(g, &c);
  release(g, &b);
  release(g, &a);
  pb_scene_destroy(&s);

  r = pb_scene_load("samples/cornell_box/cornell_box.gltf", &ld, &s);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return;
  dt.photons = da.photons = 1u << 16;
  if (trace(g, &s, &dt, 22, 0, 0, 0, 0, &a)) {
    if (trace(g, &s, &da, 22, 0, 0, 0, 0, &c)) {
      printf("cornell_box: traced %u records, auto %u (map coverage %.4f, %u lights from their map)\n", a.n, c.n,
             c.st.rsm_coverage, c.st.rsm_lights);
      CHECK_EQ_INT(c.n, a.n);
      CHECK_EQ_INT(c.st.rsm_lights, 0);
      release(g, &c);
    }
    release(g, &a);
  }
  pb_scene_destroy(&s);

  /* What auto picks on the other samples: each map's coverage (printed for
   * bench/README.md); the closed rooms keep the traced first bounce. */
  static const char *const names[] = {"cornell_caustics", "spot_room", "sun_atrium"};
  for (int i = 0; i < 3; ++i) {
    char path[256];
    snprintf(path, sizeof path, "samples/%s/%s.gltf", names[i], names[i]);
    if ((r = pb_scene_load(path, &ld, &s)) != PB_OK) {
      CHECK_EQ_INT(r, PB_OK);
      continue;
    }
    da.photons = 1u << 12;
    if (trace(g, &s, &da, 23, 0, 0, 0, 0, &c)) {
      printf("%s: map coverage %.4f, auto: %u lights from their map\n", names[i], c.st.rsm_coverage,
             c.st.rsm_lights);
      if (i < 2) CHECK_EQ_INT(c.st.rsm_lights, 0);
      release(g, &c);
    }
    pb_scene_destroy(&s);
  }
}

/* ---- (d) jitter within the texel ----------------------------------------- */

static int cmp_pos(const void *a, const void *b) {
  const float *p = a, *q = b;
  for (int k = 0; k < 3; ++k)
    if (p[k] != q[k]) return p[k] < q[k] ? -1 : 1;
  return 0;
}

/* First hits stored for the test (PB_PHOTON_PARAM_STORE_FIRST):
 *  - a point light in the box with a 16 x 16 cube map (1536 texels) and
 *    20000 photons: the photons of one texel land on distinct points (more
 *    distinct first-hit positions than texels; the texel centre alone gave
 *    at most 1536);
 *  - a 1 x 1 m plate under a 30-degree directional light, a 16 x 16 map: the
 *    first-hit flux is E cos(30) x 1 m^2 within 1.5 %, texels cut by the
 *    plate's edges included (their jittered photons that miss are lost, and
 *    texels whose centre misses but whose corner hits keep a weight). */
static void jitter(pb_gpu *g) {
  static tscene t;
  box(&t, 0.5f);
  float w[3] = {1, 1, 1};
  add_point(&t, 0.1f, 0.2f, -0.1f, 1.0f, w);
  finish(&t);
  pb_photon_trace_desc d = {.photons = 20000, .max_bounces = 1, .first_bounce = PB_FIRST_BOUNCE_RSM,
                            .rsm_resolution = 16};
  traced tr;
  if (trace(g, &t.s, &d, 5, 0, 0, 0, PB_PHOTON_PARAM_STORE_FIRST, &tr)) {
    float (*pos)[3] = calloc(tr.n ? tr.n : 1, sizeof *pos);
    uint32_t n = 0, distinct = 0;
    for (uint32_t i = 0; i < tr.n; ++i)
      if (bounce_of(&tr.ph[i]) == 0) memcpy(pos[n++], tr.ph[i].position, sizeof pos[0]);
    qsort(pos, n, sizeof *pos, cmp_pos);
    for (uint32_t i = 0; i < n; ++i) distinct += i == 0 || cmp_pos(pos[i], pos[i - 1]) != 0;
    printf("rsm jitter: %u first hits, %u distinct positions, 1536 texels\n", n, distinct);
    CHECK(n > 15000);
    CHECK(distinct > 0.9 * n);
    free(pos);
    release(g, &tr);
  }

  static tscene p;
  memset(&p, 0, sizeof p);
  uint32_t m = add_mat(&p, 0.5f, 0);
  float q[4][3] = {{-0.5f, 0, -0.5f}, {-0.5f, 0, 0.5f}, {0.5f, 0, 0.5f}, {0.5f, 0, -0.5f}};
  float up[3] = {0, 1, 0};
  add_quad(&p, q, up, m);
  pb_light *l = &p.light[p.nl++];
  memset(l, 0, sizeof *l);
  l->type = PB_LIGHT_DIRECTIONAL;
  l->direction[0] = 0.5f, l->direction[1] = -0.8660254f;
  l->color[0] = l->color[1] = l->color[2] = 1;
  l->intensity = 2.0f; /* W/m^2 */
  finish(&p);
  d = (pb_photon_trace_desc){.photons = 50000, .max_bounces = 1, .first_bounce = PB_FIRST_BOUNCE_RSM,
                             .rsm_resolution = 16};
  if (trace(g, &p.s, &d, 6, 0, 0, 0, PB_PHOTON_PARAM_STORE_FIRST, &tr)) {
    double sum = 0;
    for (uint32_t i = 0; i < tr.n; ++i)
      if (bounce_of(&tr.ph[i]) == 0) sum += tr.ph[i].power[0];
    double want = 2.0 * 0.8660254 * 1.0;
    printf("rsm jitter: plate under a directional light: first-hit flux %.5f W, expected E cos30 A = %.5f W "
           "(%+.2f %%)\n", sum, want, 100 * (sum / want - 1));
    CHECK_NEAR(sum, want, 0.015 * want);
    release(g, &tr);
  }
}

int main(void) {
  PBT_GPU_OPEN(g);
  energy(g);
  sample(g, "cornell_box", 60000, 1);
  sample(g, "sun_atrium", 120000, 0);
  sample(g, "spot_room", 40000, 0);
  jitter(g);
  ring(g);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
