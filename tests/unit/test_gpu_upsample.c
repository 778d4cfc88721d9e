/* Seed 003's multi-level up-sampling of the diffuse photon irradiance (sec.
 * 6, Figure 9; src/render/estimate/upsample.c) on a lit plane with an analytic
 * answer: a 2 x 2 m plane seen from above (it fills the view), its two
 * triangles of different albedo (0.8 and 0.2, meeting on the diagonal x = z),
 * lit by synthetic photons uploaded as a photon map: a jittered grid of discs
 * of radius 0.25 m whose power rises along x (a smooth irradiance with a
 * gradient), every third one a caustic photon. The indirect AOV of every
 * pixel must be albedo / pi * sum K / A Phi of the non-caustic photons
 * (test_gpu_gather.c's sum) at L = 0 and, within 2 % on average and 6 % at
 * worst, at L = 2: the up-sampled quantity is the irradiance, so the albedo
 * edge on the diagonal stays sharp (up-sampled radiance would blur it by
 * half the albedo step). The plane is flat: nothing is recomputed; the
 * estimate runs at ceil(65 / 4)^2 pixels per sample; the caustic photons are
 * estimated at full resolution, equal to L = 0 to float rounding. Validation
 * layers on; exit 77 without a Vulkan device. One sample per pixel: the
 * camera ray then meets the pixel centre (with more the samples spread over
 * the pixel and L = 0 differs from the centre's sum by up to 2 %).
 * Measured on lavapipe: L 0 exact to rounding; L 2 mean 0.66 %, worst 3.3 %,
 * the mean beauty 0.44 % from L 0's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "render/photon/photon.h"
#include "render/render.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"

enum { W = 65, H = 65, GRID = 60, NPH = GRID * GRID };

static uint64_t rng_state = 4242;
static float frand(void) {
  rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
  return (float)((rng_state >> 40) & 0xffffff) / 16777216.0f;
}

static double stat_of(const pb_render_result *r, const char *name) {
  return pb_render_estimator_stat(&r->stats, name, -1);
}

int main(void) {
  PBT_GPU_OPEN(g);
  float pos[4][3] = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  float nrm[4][3] = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  float uv[4][2] = {{0, 0}};
  uint32_t tri[2][3] = {{0, 2, 1}, {0, 3, 2}};
  uint32_t tm[2] = {0, 1}; /* triangle 0: x >= z, albedo 0.8; triangle 1: z >= x, 0.2 */
  const float albedo[2] = {0.8f, 0.2f};
  pb_material mat[2];
  memset(mat, 0, sizeof mat);
  for (int m = 0; m < 2; ++m) {
    mat[m].base_color[0] = mat[m].base_color[1] = mat[m].base_color[2] = albedo[m];
    mat[m].base_color[3] = 1;
    mat[m].base_color_tex = mat[m].metallic_roughness_tex = mat[m].emissive_tex = mat[m].normal_tex = PB_NO_TEXTURE;
    mat[m].roughness = 1;
    mat[m].specular = 0;
    mat[m].ior = 1.5f;
  }
  pb_camera cam;
  memset(&cam, 0, sizeof cam);
  cam.position[1] = 3;
  cam.forward[1] = -1;
  cam.up[2] = -1;
  cam.right[0] = 1;
  cam.yfov = 0.6f;
  cam.aspect = 1;
  pb_scene s;
  memset(&s, 0, sizeof s);
  s.positions = pos;
  s.normals = nrm;
  s.uvs = uv;
  s.vertex_count = 4;
  s.triangles = tri;
  s.triangle_material = tm;
  s.triangle_count = 2;
  s.materials = mat;
  s.material_count = 2;
  s.cameras = &cam;
  s.camera_count = 1;
  pb_scene_finalize(&s);

  pb_gpu_photon *ph = calloc(NPH, sizeof *ph);
  const float rad = 0.25f, span = 2.6f;
  for (int i = 0; i < NPH; ++i) {
    pb_gpu_photon *p = &ph[i];
    float x = -1.3f + span * ((i % GRID) + frand()) / GRID, z = -1.3f + span * ((i / GRID) + frand()) / GRID;
    p->position[0] = x, p->position[2] = z;
    float a = 0.002f * (1.0f + 0.6f * x); /* the gradient along x */
    p->power[0] = a, p->power[1] = 0.7f * a, p->power[2] = 0.4f * a;
    p->axis_u[0] = rad, p->axis_v[2] = rad;
    p->radius = rad;
    p->normal_extent = 0.05f;
    p->wi[1] = 1;
    p->normal[1] = 1;
    p->flags = i % 3 == 0 ? PB_PHOTON_CAUSTIC : 0u;
    p->path = (uint32_t)i;
  }
  pb_photon_map map;
  memset(&map, 0, sizeof map);
  map.capacity = NPH;
  map.stored = NPH;
  pb_gpu_buffer_desc bd = {.name = "test.photons", .size = NPH * sizeof(pb_gpu_photon)};
  CHECK_EQ_INT(pb_gpu_buffer_create(g, &bd, &map.photons), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_upload(g, &map.photons, 0, ph, NPH * sizeof(pb_gpu_photon)), PB_OK);
  /* caustic photons present: the full-resolution pass runs everywhere */
  map.caustic = (NPH + 2) / 3;

  pb_gpu_scene gs;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &s, &gs), PB_OK);
  pb_render_result res[2];
  memset(res, 0, sizeof res);
  const uint32_t levels[2] = {0, 2}, spp = 1;
  for (int k = 0; k < 2; ++k) {
    pb_render_desc rd = {.spp = spp, .upsample_levels = levels[k]};
    pb_render_io io = {.photon_map = &map};
    pb_result rr = pb_render_frame_io(g, &s, &gs, 0, W, H, &rd, &io, &res[k]);
    CHECK_EQ_INT(rr, PB_OK);
    if (rr != PB_OK) {
      fprintf(stderr, "%s\n", pb_error_message());
      return pbt_done();
    }
  }
  float tan_y = tanf(0.5f * cam.yfov), tan_x = tan_y;
  double sum_rel[2] = {0, 0}, max_rel[2] = {0, 0}, sum_diff = 0, sum_off = 0, cau_err = 0, cau_max = 0;
  uint32_t n = 0;
  for (int py = 0; py < H; ++py)
    for (int px = 0; px < W; ++px) {
      float sx = (2.0f * (px + 0.5f) / W - 1) * tan_x, sy = (1 - 2.0f * (py + 0.5f) / H) * tan_y;
      double x = 3.0 * sx, z = -3.0 * sy;
      if (fabs(x - z) < 0.03) continue; /* on the albedo edge itself: either triangle */
      double want = 0;
      for (int i = 0; i < NPH; ++i) {
        const pb_gpu_photon *p = &ph[i];
        if (p->flags & PB_PHOTON_CAUSTIC) continue;
        double dx = x - p->position[0], dz = z - p->position[2], q = (dx * dx + dz * dz) / (rad * rad);
        if (q <= 1) want += 2.0 * (1 - q) / (M_PI * rad * rad) * p->power[0];
      }
      want *= albedo[x >= z ? 0 : 1] / M_PI;
      size_t o = (size_t)py * W + px;
      for (int k = 0; k < 2; ++k) {
        double e = fabs(res[k].indirect[3 * o] - want) / want;
        sum_rel[k] += e;
        if (e > max_rel[k]) max_rel[k] = e;
      }
      sum_diff += fabs(res[1].beauty[4 * o] - res[0].beauty[4 * o]);
      sum_off += res[0].beauty[4 * o];
      for (int c = 0; c < 3; ++c) {
        double d = fabs(res[1].caustic[3 * o + c] - res[0].caustic[3 * o + c]);
        if (d > cau_err) cau_err = d;
        if (res[0].caustic[3 * o + c] > cau_max) cau_max = res[0].caustic[3 * o + c];
      }
      ++n;
    }
  double coarse = stat_of(&res[1], "upsample_coarse"), recomputed = stat_of(&res[1], "upsample_recomputed");
  double interpolated = stat_of(&res[1], "upsample_interpolated"), full = stat_of(&res[1], "upsample_full_res");
  double want_coarse = (double)spp * ((W + 3) / 4) * ((H + 3) / 4);
  printf("lit plane %dx%d, %u spp, %d photons: |indirect - analytic| / analytic mean %.4f max %.4f at L 0, "
         "mean %.4f max %.4f at L 2; beauty |L2 - L0| / L0 (means) %.4f; caustic max |L2 - L0| %.3g of %.3g; "
         "L 2: coarse %.0f (want %.0f), recomputed %.0f, interpolated %.0f, full-res %.0f; gather %.2f ms\n",
         W, H, spp, NPH, sum_rel[0] / n, max_rel[0], sum_rel[1] / n, max_rel[1], sum_diff / sum_off, cau_err, cau_max,
         coarse, want_coarse, recomputed, interpolated, full, res[1].stats.gather_ms);
  CHECK(n > 3000);
  CHECK(sum_rel[0] / n < 2e-4 && max_rel[0] < 2e-3); /* L 0 is the plain gather */
  CHECK(sum_rel[1] / n <= 0.02);
  CHECK(max_rel[1] <= 0.06);
  CHECK(sum_diff / sum_off <= 0.02);
  CHECK(cau_max > 0 && cau_err <= 1e-5 * cau_max);
  CHECK(coarse == want_coarse);
  CHECK(recomputed == 0);
  CHECK(interpolated == (double)spp * W * H - want_coarse);
  CHECK(full == (double)spp * W * H);
  CHECK_EQ_INT((int)res[1].stats.nonfinite_values, 0);
  CHECK(stat_of(&res[0], "upsample_levels") < 0); /* off: no such statistics */
  for (int k = 0; k < 2; ++k) pb_render_result_destroy(&res[k]);
  pb_gpu_scene_destroy(g, &gs);
  pb_photon_map_destroy(g, &map);
  free(ph);
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
