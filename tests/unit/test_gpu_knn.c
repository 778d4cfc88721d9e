/* kNN photon mapping (seed 000 3.1; src/render/estimate/estimator_knn.c,
 * shaders/estimate/knn.comp):
 *  (a) a lit plane: photons of equal power on a jittered grid over a 2 x 2 m
 *      Lambert plane (albedo 0.8), seen from above (pixel centres on known
 *      points): every pixel equals a brute-force k-nearest-neighbour
 *      estimate on the host (Epanechnikov, k = 64, the k-th distance as the
 *      bandwidth; to 1e-3 of the peak: the heap and the box-pruned search
 *      are exact), and the interior's mean radiance is the analytic
 *      albedo / pi * N Phi / A within 2 %; photons on the plane's other
 *      side count nothing; caustic photons go to their own AOV;
 *  (b) flux: photons from a smooth density varying nine-fold over and past
 *      the plane: the irradiance integrated over a window of pixels is the
 *      stored power in it within 2 %;
 *  (c) determinism: the same host map twice gives the same pixels, bit for
 *      bit; k = 8 and k = 256 give the same mean (the estimate is unbiased
 *      on a uniform density) and 256 a smoother picture;
 *  (d) cornell_box at a high photon count (2^17 paths, 8 maps, 48 px)
 *      against the LBVH gather: mean indirect within 2 %, PSNR above
 *      KNN_LBVH_PSNR_MIN, and both against the reference's beauty;
 *  (e) hard cases: a spot of 0.5 degree (photons at the emission pole) and
 *      two parallel mirrors over a floor: no non-finite value.
 * Validation layers on; exit 77 without a Vulkan device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metrics/metrics.h"
#include "pbtest.h"
#include "gpu_test.h"
#include "sample_fixture.h"
#include "ref/ref.h"
#include "render/estimate/estimator.h"
#include "render/photon/photon.h"
#include "render/render.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_knn.h"

/* Measured (llvmpipe, 48 px, 2^17 paths, 8 maps): see the printout;
 * thresholds leave a margin of a few dB. */
#define KNN_LBVH_PSNR_MIN 30.0

static uint64_t rng_state = 4242;
static float frand(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (float)((rng_state >> 40) & 0xffffff) / 16777216.0f;
}

enum { W = 41, H = 41, K = 64 };
static const float ALBEDO = 0.8f, R_MAX = 0.5f;

typedef struct plane {
  float pos[4][3], nrm[4][3], uv[4][2];
  uint32_t tri[2][3], tm[2];
  pb_material mat;
  pb_camera cam;
  pb_scene s;
} plane;

static void plane_make(plane *p) {
  memset(p, 0, sizeof *p);
  const float pos[4][3] = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  memcpy(p->pos, pos, sizeof pos);
  for (int i = 0; i < 4; ++i) p->nrm[i][1] = 1;
  const uint32_t tri[2][3] = {{0, 2, 1}, {0, 3, 2}};
  memcpy(p->tri, tri, sizeof tri);
  pb_material *m = &p->mat;
  m->base_color[0] = m->base_color[1] = m->base_color[2] = ALBEDO;
  m->base_color[3] = 1;
  m->base_color_tex = m->metallic_roughness_tex = m->emissive_tex = m->normal_tex = PB_NO_TEXTURE;
  m->roughness = 1;
  m->specular = 0;
  m->ior = 1.5f;
  p->cam.position[1] = 3;
  p->cam.forward[1] = -1;
  p->cam.up[2] = -1;
  p->cam.right[0] = 1;
  p->cam.yfov = 0.6f;
  p->cam.aspect = 1;
  pb_scene *s = &p->s;
  s->positions = p->pos;
  s->normals = p->nrm;
  s->uvs = p->uv;
  s->vertex_count = 4;
  s->triangles = p->tri;
  s->triangle_material = p->tm;
  s->triangle_count = 2;
  s->materials = &p->mat;
  s->material_count = 1;
  s->cameras = &p->cam;
  s->camera_count = 1;
  pb_scene_finalize(s);
}

/* The plane point at the centre of pixel (px, py). */
static void pixel_point(const plane *p, int px, int py, double *x, double *z) {
  double t = tan(0.5 * p->cam.yfov);
  *x = 3.0 * (2.0 * (px + 0.5) / W - 1) * t;
  *z = -3.0 * (1 - 2.0 * (py + 0.5) / H) * t;
}

/* n photons on a jittered grid over [-e, e]^2 (and `back` on the other side,
 * normal -y), power (0.01, 0.006, 0.003) W each; every third caustic. */
static pb_gpu_photon *photons_grid(int side, float e, int back, uint32_t *n_out) {
  uint32_t n = (uint32_t)(side * side + back);
  pb_gpu_photon *ph = calloc(n, sizeof *ph);
  uint32_t i = 0;
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b, ++i) {
      pb_gpu_photon *q = &ph[i];
      q->position[0] = -e + 2 * e * (a + frand()) / side;
      q->position[2] = -e + 2 * e * (b + frand()) / side;
      q->power[0] = 0.01f, q->power[1] = 0.006f, q->power[2] = 0.003f;
      q->normal[1] = 1;
      q->wi[1] = 1;
      q->axis_u[0] = q->axis_v[2] = 0.05f; /* footprints only size the LBVH's boxes here */
      q->radius = 0.05f;
      q->normal_extent = 0.01f;
      q->flags = i % 3 == 0 ? PB_PHOTON_CAUSTIC : 0u;
      q->path = i;
    }
  for (int k = 0; k < back; ++k, ++i) { /* the other side: never counted */
    pb_gpu_photon *q = &ph[i];
    q->position[0] = 2 * e * frand() - e, q->position[2] = 2 * e * frand() - e;
    q->power[0] = q->power[1] = q->power[2] = 1.0f;
    q->normal[1] = -1;
    q->wi[1] = -1;
    q->axis_u[0] = q->axis_v[2] = 0.05f;
    q->radius = 0.05f;
    q->normal_extent = 0.01f;
    q->path = i;
  }
  *n_out = n;
  return ph;
}

static int upload_map(pb_gpu *g, const pb_gpu_photon *ph, uint32_t n, pb_photon_map *map) {
  memset(map, 0, sizeof *map);
  map->capacity = n;
  map->stored = n;
  pb_gpu_buffer_desc bd = {.name = "test.photons", .size = (uint64_t)n * sizeof(pb_gpu_photon)};
  if (pb_gpu_buffer_create(g, &bd, &map->photons) != PB_OK) return 0;
  return pb_gpu_buffer_upload(g, &map->photons, 0, ph, (uint64_t)n * sizeof(pb_gpu_photon)) == PB_OK;
}

static pb_result render_knn(pb_gpu *g, const plane *p, const pb_gpu_scene *gs, const pb_photon_map *map, uint32_t k,
                            pb_render_result *res) {
  pb_render_desc rd = {.estimator = {.kind = PB_ESTIMATOR_KNN, .knn = {.k = k, .r_max = R_MAX}}};
  pb_render_io io = {.photon_map = map};
  return pb_render_frame_io(g, &p->s, gs, 0, W, H, &rd, &io, res);
}

/* Brute force: the k nearest same-side photons of (x, 0, z) within R_MAX. */
static void host_knn(const pb_gpu_photon *ph, uint32_t n, double x, double z, uint32_t k, double out[2][3]) {
  double *d2 = malloc(n * sizeof *d2);
  uint32_t *idx = malloc(n * sizeof *idx), m = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (!(ph[i].normal[1] > 0)) continue;
    double dx = x - ph[i].position[0], dz = z - ph[i].position[2], d = dx * dx + dz * dz;
    if (d < (double)R_MAX * R_MAX) d2[m] = d, idx[m] = i, m++;
  }
  /* partial selection sort of the k smallest */
  uint32_t kk = m < k ? m : k;
  for (uint32_t a = 0; a < kk; ++a) {
    uint32_t b = a;
    for (uint32_t c = a + 1; c < m; ++c)
      if (d2[c] < d2[b]) b = c;
    double td = d2[a];
    uint32_t ti = idx[a];
    d2[a] = d2[b], idx[a] = idx[b], d2[b] = td, idx[b] = ti;
  }
  double r2 = kk == k ? d2[k - 1] : (double)R_MAX * R_MAX;
  memset(out, 0, 6 * sizeof(double));
  for (uint32_t a = 0; a < kk; ++a) {
    const pb_gpu_photon *q = &ph[idx[a]];
    double w = 2.0 * (1.0 - d2[a] / r2) / (M_PI * r2) * ALBEDO / M_PI;
    for (int c = 0; c < 3; ++c) out[(q->flags & PB_PHOTON_CAUSTIC) ? 1 : 0][c] += w * q->power[c];
  }
  free(d2);
  free(idx);
}

static void lit_plane(pb_gpu *g) {
  plane p;
  plane_make(&p);
  uint32_t n;
  const int side = 64; /* 4096 photons on 4 m^2: k = 64 within r ~ 0.14 m */
  pb_gpu_photon *ph = photons_grid(side, 1.0f, 300, &n);
  pb_photon_map map;
  pb_gpu_scene gs;
  pb_render_result a, b;
  memset(&a, 0, sizeof a);
  memset(&b, 0, sizeof b);
  CHECK(upload_map(g, ph, n, &map));
  CHECK_EQ_INT(pb_gpu_scene_create(g, &p.s, &gs), PB_OK);
  pb_result r = render_knn(g, &p, &gs, &map, K, &a);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  if (r == PB_OK) {
    CHECK(a.stats.estimator && !strcmp(a.stats.estimator, "knn"));
    CHECK_EQ_INT((int)pb_render_estimator_stat(&a.stats, "k", 0), K);
    double max_err = 0, peak = 0, sum = 0, sum_c = 0, beauty_err = 0;
    uint32_t inner = 0;
    double phi_front = 0;
    for (uint32_t i = 0; i < n; ++i)
      if (ph[i].normal[1] > 0) phi_front += ph[i].power[0];
    double want_mean = ALBEDO / M_PI * phi_front / 4.0; /* red: rho / pi * N Phi / A */
    for (int py = 0; py < H; ++py)
      for (int px = 0; px < W; ++px) {
        double x, z;
        pixel_point(&p, px, py, &x, &z);
        if (fabs(x) > 0.99 || fabs(z) > 0.99) continue;
        double want[2][3];
        host_knn(ph, n, x, z, K, want);
        size_t o = (size_t)py * W + px;
        for (int c = 0; c < 3; ++c) {
          for (int f = 0; f < 2; ++f) {
            double got = f ? a.caustic[3 * o + c] : a.indirect[3 * o + c];
            if (fabs(got - want[f][c]) > max_err) max_err = fabs(got - want[f][c]);
            if (want[f][c] > peak) peak = want[f][c];
          }
          double be = fabs(a.beauty[4 * o + c] - a.indirect[3 * o + c] - a.caustic[3 * o + c]);
          if (be > beauty_err) beauty_err = be;
        }
        if (fabs(x) < 0.75 && fabs(z) < 0.75) { /* away from the plane's open edges */
          sum += a.indirect[3 * o] + a.caustic[3 * o];
          sum_c += a.caustic[3 * o];
          inner++;
        }
      }
    double mean = sum / inner;
    printf("knn lit plane: %u photons, k %d: max |GPU - host kNN| %.3g of peak %.3g; interior mean %.5f vs analytic "
           "%.5f (%+.2f %%), caustic share %.3f; k_PD %.1f, build %.2f ms, query %.2f ms\n",
           n, K, max_err, peak, mean, want_mean, 100 * (mean / want_mean - 1), sum_c / sum, a.stats.k_pd,
           a.stats.estimator_build_ms, a.stats.gather_ms);
    CHECK(max_err <= 1e-3 * peak);
    CHECK(fabs(mean / want_mean - 1) < 0.02);
    CHECK(fabs(sum_c / sum - 1.0 / 3.0) < 0.03);
    CHECK(beauty_err <= 1e-5 * peak);
    CHECK(a.stats.k_pd > K - 1 && a.stats.k_pd <= K);
    /* (c) the same map again: the same pixels, bit for bit. */
    r = render_knn(g, &p, &gs, &map, K, &b);
    CHECK_EQ_INT(r, PB_OK);
    if (r == PB_OK) {
      size_t diff = 0;
      for (size_t i = 0; i < (size_t)3 * W * H; ++i) diff += a.indirect[i] != b.indirect[i] || a.caustic[i] != b.caustic[i];
      printf("knn determinism: %zu of %d values differ\n", diff, 3 * W * H);
      CHECK_EQ_INT((int)diff, 0);
    }
    /* (c) k = 8 and 256: the same mean on a uniform density, less noise with more. */
    double mk[2] = {0, 0}, vk[2] = {0, 0};
    const uint32_t ks[2] = {8, 256};
    for (int t = 0; t < 2; ++t) {
      pb_render_result c;
      memset(&c, 0, sizeof c);
      r = render_knn(g, &p, &gs, &map, ks[t], &c);
      CHECK_EQ_INT(r, PB_OK);
      if (r != PB_OK) break;
      uint32_t m = 0;
      for (int py = 0; py < H; ++py)
        for (int px = 0; px < W; ++px) {
          double x, z;
          pixel_point(&p, px, py, &x, &z);
          if (fabs(x) >= 0.6 || fabs(z) >= 0.6) continue;
          size_t o = (size_t)py * W + px;
          double v = c.indirect[3 * o] + c.caustic[3 * o];
          mk[t] += v, vk[t] += v * v, m++;
        }
      mk[t] /= m;
      vk[t] = sqrt(fmax(vk[t] / m - mk[t] * mk[t], 0)) / mk[t];
      pb_render_result_destroy(&c);
    }
    printf("knn k 8: mean %.5f, rel. std %.4f; k 256: mean %.5f, rel. std %.4f (analytic %.5f)\n", mk[0], vk[0],
           mk[1], vk[1], want_mean);
    CHECK(fabs(mk[0] / want_mean - 1) < 0.04 && fabs(mk[1] / want_mean - 1) < 0.02);
    CHECK(vk[1] < 0.6 * vk[0]);
  }
  pb_render_result_destroy(&a);
  pb_render_result_destroy(&b);
  pb_gpu_scene_destroy(g, &gs);
  pb_photon_map_destroy(g, &map);
  free(ph);
  pb_error_clear();
}

/* (b) flux: photons of equal power drawn from a smooth density varying
 * nine-fold, d(x, z) = 1 + 0.8 sin(2 x) sin(1.5 z), over [-1.5, 1.5]^2 (past
 * the plane's edges, so no pixel sees the end of the map). The irradiance
 * E = pi L / albedo integrated over the pixels of a window equals the
 * stored power of the photons in it within 2 %. (Not a map with an edge of
 * its own: kNN's estimate beyond the last photons falls off only as the
 * k-th distance grows, to r_max, so there it spreads flux outwards: +13 %
 * measured for a 0.6 m square of photons with r_max 0.5 m.) */
static void flux(pb_gpu *g) {
  plane p;
  plane_make(&p);
  enum { N = 20000 };
  pb_gpu_photon *ph = calloc(N, sizeof *ph);
  uint32_t n = 0;
  while (n < N) {
    float x = 3.0f * frand() - 1.5f, z = 3.0f * frand() - 1.5f;
    if (1.8f * frand() > 1.0f + 0.8f * sinf(2.0f * x) * sinf(1.5f * z)) continue;
    pb_gpu_photon *q = &ph[n];
    q->position[0] = x, q->position[2] = z;
    q->power[0] = q->power[1] = q->power[2] = 1e-3f;
    q->normal[1] = 1, q->wi[1] = 1;
    q->axis_u[0] = q->axis_v[2] = 0.05f;
    q->radius = 0.05f, q->normal_extent = 0.01f;
    q->path = n++;
  }
  pb_photon_map map;
  pb_gpu_scene gs;
  pb_render_result a;
  memset(&a, 0, sizeof a);
  CHECK(upload_map(g, ph, n, &map));
  CHECK_EQ_INT(pb_gpu_scene_create(g, &p.s, &gs), PB_OK);
  pb_result r = render_knn(g, &p, &gs, &map, K, &a);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK) {
    /* Pixels cover (6 tan(fov / 2) / W)^2 m^2 each (the camera looks
     * straight down from 3 m); the window: the pixels whose centres lie in
     * [-0.8, 0.8]^2, the area they tile. */
    double step = 6.0 * tan(0.5 * p.cam.yfov) / W, e = 0, lo = 1e9, hi = -1e9, phi = 0;
    for (int py = 0; py < H; ++py)
      for (int px = 0; px < W; ++px) {
        double x, z;
        pixel_point(&p, px, py, &x, &z);
        if (fabs(x) > 0.8 || fabs(z) > 0.8) continue;
        size_t o = (size_t)py * W + px;
        e += a.indirect[3 * o] * M_PI / ALBEDO * step * step;
        lo = fmin(lo, x), hi = fmax(hi, x);
      }
    lo -= 0.5 * step, hi += 0.5 * step;
    for (uint32_t i = 0; i < n; ++i)
      if (ph[i].position[0] >= lo && ph[i].position[0] < hi && ph[i].position[2] >= lo && ph[i].position[2] < hi)
        phi += ph[i].power[0];
    printf("knn flux: %u photons; in the %.3f m window: stored %.4f W, estimated %.4f W (%+.2f %%)\n", n, hi - lo,
           phi, e, 100 * (e / phi - 1));
    CHECK(fabs(e / phi - 1) < 0.02);
  }
  pb_render_result_destroy(&a);
  pb_gpu_scene_destroy(g, &gs);
  pb_photon_map_destroy(g, &map);
  free(ph);
  pb_error_clear();
}

/* (d) cornell_box: kNN against the LBVH gather and the reference. */
static void cornell(pb_gpu *g) {
  pbt_sample f;
  pb_ref_desc fd = {.spp = 256, .seed = 9};
  if (!pbt_sample_open(g, "cornell_box", 48, &fd, &f)) {
    pbt_sample_close(g, &f);
    return;
  }
  pb_render_result res[2];
  memset(res, 0, sizeof res);
  double mean_ind[2] = {0, 0}, psnr_ref[2] = {0, 0};
  for (int e = 0; e < 2; ++e) {
    pb_render_desc rd = {.spp = 16, .seed = 5, .photons = 1u << 17, .iterations = 8,
                         .estimator = {.kind = e ? PB_ESTIMATOR_KNN : PB_ESTIMATOR_LBVH}};
    pb_result r = pb_render_frame(g, &f.s, &f.gs, 0, f.w, f.h, &rd, &res[e]);
    CHECK_EQ_INT(r, PB_OK);
    if (r != PB_OK) {
      fprintf(stderr, "%s\n", pb_error_message());
      goto done;
    }
    for (size_t i = 0; i < (size_t)f.w * f.h; ++i)
      for (int c = 0; c < 3; ++c) mean_ind[e] += res[e].indirect[3 * i + c] + res[e].caustic[3 * i + c];
    mean_ind[e] /= 3.0 * f.w * f.h;
    pb_metrics m;
    CHECK_EQ_INT(pb_metrics_compute(res[e].beauty, f.ref.beauty, f.w, f.h, 4, NULL, &m), PB_OK);
    psnr_ref[e] = m.psnr;
    CHECK_EQ_INT(res[e].stats.nonfinite_values, 0);
  }
  pb_metrics mk;
  CHECK_EQ_INT(pb_metrics_compute(res[1].beauty, res[0].beauty, f.w, f.h, 4, NULL, &mk), PB_OK);
  printf("cornell_box %ux%u, 16 spp, 8 x 2^17 paths: mean indirect kNN %.5f, LBVH %.5f (%+.2f %%); kNN vs LBVH "
         "%.2f dB; vs the reference: kNN %.2f dB, LBVH %.2f dB; k_PD kNN %.1f, LBVH %.1f; query kNN %.1f ms, "
         "gather %.1f ms\n",
         f.w, f.h, mean_ind[1], mean_ind[0], 100 * (mean_ind[1] / mean_ind[0] - 1), mk.psnr, psnr_ref[1],
         psnr_ref[0], res[1].stats.k_pd, res[0].stats.k_pd, res[1].stats.gather_ms, res[0].stats.gather_ms);
  CHECK(fabs(mean_ind[1] / mean_ind[0] - 1) < 0.02);
  CHECK(mk.psnr > KNN_LBVH_PSNR_MIN);
  CHECK(psnr_ref[1] > psnr_ref[0] - 3.0);
done:
  pb_render_result_destroy(&res[0]);
  pb_render_result_destroy(&res[1]);
  pbt_sample_close(g, &f);
  pb_error_clear();
}

/* ---- (e) hard cases: code-built scenes (gpu_scene_helpers.h) ------------- */

#include "gpu_scene_helpers.h"

static const float white[3] = {1, 1, 1};

/* Renders t with kNN (traced photons); its values must all be finite, and
 * some indirect light there. */
static void hard_render(pb_gpu *g, tscene *t, const char *what) {
  pb_gpu_scene gs;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &t->s, &gs), PB_OK);
  pb_render_result res;
  memset(&res, 0, sizeof res);
  pb_render_desc rd = {.spp = 2, .seed = 7, .photons = 1u << 15, .iterations = 2,
                       .estimator = {.kind = PB_ESTIMATOR_KNN}};
  pb_result r = pb_render_frame(g, &t->s, &gs, 0, 24, 24, &rd, &res);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK) {
    size_t bad = 0;
    double sum = 0;
    for (size_t i = 0; i < (size_t)3 * 24 * 24; ++i) {
      bad += !isfinite(res.indirect[i]) || !isfinite(res.caustic[i]) || !isfinite(res.beauty[i / 3 * 4 + i % 3]);
      sum += res.indirect[i] + res.caustic[i];
    }
    printf("knn hard: %s: %llu photons stored, %zu non-finite values (%llu guarded), mean indirect %.4g\n", what,
           (unsigned long long)res.stats.photons_stored, bad, (unsigned long long)res.stats.nonfinite_values,
           sum / (3 * 24 * 24));
    CHECK_EQ_INT((int)bad, 0);
    CHECK_EQ_INT((int)res.stats.nonfinite_values, 0);
    CHECK(sum > 0);
  }
  pb_render_result_destroy(&res);
  pb_gpu_scene_destroy(g, &gs);
  pb_error_clear();
}

static void hard_cases(pb_gpu *g) {
  /* A spot of 0.5 degree straight down in a closed box of albedo 0.7:
   * every photon at the emission pole. */
  static tscene t;
  memset(&t, 0, sizeof t);
  uint32_t m = add_mat(&t, 0.7f, 0);
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2) {
      int u = (axis + 1) % 3, v = (axis + 2) % 3;
      float q[4][3], n[3] = {0, 0, 0};
      float c[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (int i = 0; i < 4; ++i) q[i][axis] = (float)side, q[i][u] = c[i][0], q[i][v] = c[i][1];
      n[axis] = (float)-side;
      add_quad(&t, q, n, m);
    }
  add_point(&t, 0, 0.99f, 0, 50.0f, white);
  t.light[0].type = PB_LIGHT_SPOT;
  t.light[0].direction[1] = -1;
  t.light[0].outer_cone = 0.5f * (float)M_PI / 180.0f;
  t.light[0].inner_cone = 0.25f * (float)M_PI / 180.0f;
  const float in_box[3] = {0, 0.9f, 0.5f};
  finish_with_camera(&t, in_box, 0.3f);
  hard_render(g, &t, "spot of 0.5 deg at the emission pole");
  /* Two parallel mirrors 1 m apart, 40 m long, over a diffuse floor. */
  memset(&t, 0, sizeof t);
  uint32_t mirror = add_mat(&t, 0.95f, 1.0f), floor_m = add_mat(&t, 0.5f, 0);
  float L = 20.0f;
  float left[4][3] = {{-0.5f, 0, -L}, {-0.5f, 0, L}, {-0.5f, 2, L}, {-0.5f, 2, -L}};
  float right[4][3] = {{0.5f, 0, -L}, {0.5f, 2, -L}, {0.5f, 2, L}, {0.5f, 0, L}};
  float nl[3] = {1, 0, 0}, nr[3] = {-1, 0, 0}, nf[3] = {0, 1, 0};
  add_quad(&t, left, nl, mirror);
  add_quad(&t, right, nr, mirror);
  float fl[4][3] = {{-0.5f, 0, -L}, {0.5f, 0, -L}, {0.5f, 0, L}, {-0.5f, 0, L}};
  add_quad(&t, fl, nf, floor_m);
  add_point(&t, 0.1f, 1.0f, 0, 10.0f, white);
  const float above[3] = {0, 1.5f, 1.0f};
  finish_with_camera(&t, above, 0.6f);
  hard_render(g, &t, "parallel mirrors");
}

int main(void) {
  PBT_GPU_OPEN(g);
  lit_plane(g);
  flux(g);
  cornell(g);
  hard_cases(g);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
