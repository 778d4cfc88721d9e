/* Smooth-shaded meshes. The photon density on a face
 * carries |w_i . n_g|, the BSDF's cosine is |w_i . n_s|: the gather weights
 * each photon by |w_i . n_s| / |w_i . n_g| of the face it hit, and the
 * photon tracer's smooth scattering by the adjoint factor
 * |wo . n_s| |wi . n_g| / (|wo . n_g| |wi . n_s|) (Veach 1997, 5.3; the
 * reference's pb_photon_gather). Two scenes, Lambert 0.75, point lights,
 * the mean indirect light (two or more scattering events) over the pixels of
 * material 1, GPU (photon gather, defaults, 4 maps of 2^15) against the
 * Embree reference (path tracing, 256 spp, 1024 events), within 5 %:
 *  - a floor whose vertex normals all lean 30 degrees toward a lit wall
 *    (light -> wall -> floor arrives where |w.n_s| >> |w.n_g|). Measured on
 *    lavapipe: -3.9 % (-2.5 % since the gather renormalises its kernel at
 *    the floor's edge with the wall); without either weight -23.9 %, with
 *    the gather's alone +16.6 % (the tilted floor then sends too much to the
 *    wall);
 *  - a coarse sphere (80 faces, normals up to 19 degrees off) in a closed
 *    room: +3.1 % (+2.1 % without the weights; its flat-shaded twin +1.6 %:
 *    the gather's own bias on a curved surface, not the shading normals).
 * 48 x 48 px. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "test_ref_scene.h"
#include "ref/ref.h"
#include "render/render.h"

static const float RHO = 0.75f;
static const float R = 0.45f, CX = 0.1f, CY = -0.55f, CZ = 0.0f;

static uint32_t sphere_vertex(pb_scene *s, const float d_in[3]) {
  float d[3] = {d_in[0], d_in[1], d_in[2]};
  tsc_norm3(d);
  float p[3] = {CX + R * d[0], CY + R * d[1], CZ + R * d[2]};
  return tsc_vertex(s, p, d); /* smooth: the normal is the sphere's */
}

static void sphere(pb_scene *s, uint32_t mat) {
  const float t = (1.0f + sqrtf(5.0f)) / 2.0f;
  float v[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  static const int f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                               {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                               {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                               {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int i = 0; i < 20; ++i) {
    float m[3][3];
    const float *a[3] = {v[f[i][0]], v[f[i][1]], v[f[i][2]]};
    float an[3][3];
    for (int k = 0; k < 3; ++k) {
      memcpy(an[k], a[k], sizeof an[k]);
      tsc_norm3(an[k]);
    }
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) m[k][c] = 0.5f * (an[k][c] + an[(k + 1) % 3][c]);
    const float *tt[4][3] = {{an[0], m[0], m[2]}, {m[0], an[1], m[1]}, {m[2], m[1], an[2]}, {m[0], m[1], m[2]}};
    for (int q = 0; q < 4; ++q) {
      if (getenv("T_FLAT")) {
        float pa[3], pb[3], pc[3], d[3];
        for (int c = 0; c < 3; ++c) d[c] = tt[q][0][c];
        tsc_norm3(d);
        for (int c = 0; c < 3; ++c) pa[c] = (c == 0 ? CX : c == 1 ? CY : CZ) + R * d[c];
        for (int c = 0; c < 3; ++c) d[c] = tt[q][1][c];
        tsc_norm3(d);
        for (int c = 0; c < 3; ++c) pb[c] = (c == 0 ? CX : c == 1 ? CY : CZ) + R * d[c];
        for (int c = 0; c < 3; ++c) d[c] = tt[q][2][c];
        tsc_norm3(d);
        for (int c = 0; c < 3; ++c) pc[c] = (c == 0 ? CX : c == 1 ? CY : CZ) + R * d[c];
        tsc_triangle(s, pa, pb, pc, mat);
        continue;
      }
      uint32_t i0 = sphere_vertex(s, tt[q][0]), i1 = sphere_vertex(s, tt[q][1]), i2 = sphere_vertex(s, tt[q][2]);
      tsc_triangle_idx(s, i0, i1, i2, mat);
    }
  }
}

/* The second case: a floor quad (y = -1, 2 x 2 m) whose four vertex normals
 * all lean 30 degrees toward a lit wall (x = +1, facing the room), so its
 * indirect light (light -> wall -> floor) arrives where |w_i . n_s| is much
 * larger than |w_i . n_g|; a point light near the wall. */
static void tilted_floor(pb_scene *s) {
  tsc_init(s);
  uint32_t m = tsc_material(s, tsc_lambert(RHO, RHO, RHO));
  uint32_t mf = tsc_material(s, tsc_lambert(RHO, RHO, RHO));
  float n[3] = {0.5f, 0.8660254f, 0.0f};
  float p[4][3] = {{-1, -1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, -1, -1}};
  uint32_t v[4];
  for (int i = 0; i < 4; ++i) v[i] = tsc_vertex(s, p[i], n);
  tsc_triangle_idx(s, v[0], v[1], v[2], mf);
  tsc_triangle_idx(s, v[0], v[2], v[3], mf);
  float a[3] = {1, -1, -1}, b[3] = {1, -1, 1}, c[3] = {1, 1, 1}, d[3] = {1, 1, -1};
  tsc_quad(s, a, b, c, d, m); /* faces -x */
  pb_light *l = tsc_light(s, PB_LIGHT_POINT);
  l->position[0] = 0.3f, l->position[1] = 0.2f, l->position[2] = 0.0f;
  l->intensity = 2.0f;
  float pos[3] = {-0.2f, 1.2f, 0.0f}, fwd[3] = {0.15f, -1.0f, 0.0f}, up[3] = {1, 0, 0};
  tsc_camera(s, pos, fwd, up, 70.0f);
  pb_scene_finalize(s);
}

static void scene(pb_scene *s) {
  tsc_init(s);
  uint32_t m = tsc_material(s, tsc_lambert(RHO, RHO, RHO));
  uint32_t ms = tsc_material(s, tsc_lambert(RHO, RHO, RHO));
  float c[8][3];
  for (int i = 0; i < 8; ++i) {
    c[i][0] = (i & 1) ? 1.0f : -1.0f;
    c[i][1] = (i & 2) ? 1.0f : -1.0f;
    c[i][2] = (i & 4) ? 1.0f : -1.0f;
  }
  static const int q[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                              {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (int f = 0; f < 6; ++f) tsc_quad(s, c[q[f][0]], c[q[f][1]], c[q[f][2]], c[q[f][3]], m);
  sphere(s, ms);
  pb_light *l = tsc_light(s, PB_LIGHT_POINT);
  l->position[0] = -0.3f, l->position[1] = 0.8f, l->position[2] = -0.4f;
  l->intensity = 2.0f;
  float pos[3] = {0.1f, -0.3f, 0.95f}, fwd[3] = {0.0f, -0.25f, -1.0f}, up[3] = {0, 1, 0};
  tsc_camera(s, pos, fwd, up, 60.0f);
  pb_scene_finalize(s);
}

/* Mean indirect light over the pixels of material index 1 (the sphere, the
 * tilted floor), GPU against the reference; returns GPU / reference - 1. */
static double compare(pb_gpu *g, void (*build)(pb_scene *), const char *name) {
  pb_scene s;
  build(&s);
  enum { W = 48, H = 48 };
  double out = NAN;
  pb_ref_desc fd = {.spp = 256, .max_bounces = 1024, .seed = 7, .mode = PB_REF_MODE_PT, .threads = 2};
  pb_ref_result rr;
  memset(&rr, 0, sizeof rr);
  pb_result r = pb_ref_render(&s, 0, W, H, &fd, &rr);
  CHECK_EQ_INT(r, PB_OK);
  pb_gpu_scene gs;
  r = pb_gpu_scene_create(g, &s, &gs);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK || !rr.beauty) goto out;
  pb_render_desc rd = {.spp = 4, .seed = 1, .photons = 1u << 15, .iterations = 4};
  pb_render_result gr;
  memset(&gr, 0, sizeof gr);
  r = pb_render_frame(g, &s, &gs, 0, W, H, &rd, &gr);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK && gr.indirect && gr.material) {
    /* Pixels whose every sample saw material 1 (index + 1 in the AOV). */
    double sg = 0, sr = 0, sr2 = 0;
    uint32_t n = 0;
    for (uint32_t i = 0; i < W * H; ++i) {
      if (gr.material[i] != 2.0f || rr.beauty[4 * i + 3] < 1.0f) continue;
      double gi = 0, ri = 0;
      for (int c = 0; c < 3; ++c) {
        gi += gr.indirect[3 * i + c] / 3.0;
        ri += rr.indirect[3 * i + c] / 3.0;
      }
      sg += gi, sr += ri, sr2 += ri * ri;
      n++;
    }
    CHECK(n > 200);
    if (n) {
      double mg = sg / n, mr = sr / n;
      /* The pixels' spread over sqrt(n): an upper bound of the reference
       * mean's noise (the spread is mostly signal). */
      double sd = sqrt(fmax(0.0, sr2 / n - mr * mr)) / sqrt((double)n);
      out = mg / mr - 1.0;
      printf("%s: %u pixels, indirect mean GPU %.5f, reference %.5f (+- %.5f), GPU %+.2f %%; photons emitted "
             "%llu, stored %llu, k_PD %.1f\n",
             name, n, mg, mr, sd, 100.0 * out, (unsigned long long)gr.stats.photons_emitted,
             (unsigned long long)gr.stats.photons_stored, gr.stats.k_pd);
    }
  } else if (r != PB_OK) {
    fprintf(stderr, "%s\n", pb_error_message());
  }
  pb_render_result_destroy(&gr);
  pb_gpu_scene_destroy(g, &gs);
out:
  pb_ref_result_destroy(&rr);
  pb_scene_destroy(&s);
  return out;
}

int main(void) {
  PBT_GPU_OPEN(g);
  double floor = compare(g, tilted_floor, "tilted floor");
  CHECK(fabs(floor) < 0.05);
  double sph = compare(g, scene, "smooth sphere");
  CHECK(fabs(sph) < 0.05);
  pb_gpu_destroy(g);
  return pbt_done();
}
