/* `--direct-only` GPU renders against the Embree reference's direct AOV
 * (src/ref, max_bounces 1) on cornell_box, spot_room and sun_atrium: relMSE
 * (src/metrics) below 1e-3, both renderers at 64 spp (at 16 spp jitter noise
 * at edges alone gives about 1e-3), so
 * the only differences are pixel-jitter noise at edges and float rounding.
 * Plus an analytic check (a plane under a point light: rho/pi I cos / d^2)
 * and the specular chain on ring (mirror) and cornell_caustics (glass) for
 * finiteness; an emissive-quad scene built here (area lights: next-event
 * estimation toward emitters vs the reference's MIS, relMSE < 1e-3). Validation layers on, any message fatal. Exit 77 without a
 * Vulkan device. Small images: the machine is shared. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "metrics/metrics.h"
#include "pbtest.h"
#include "gpu_test.h"
#include "ref/ref.h"
#include "render/render.h"

static void compare_scene(pb_gpu *g, const char *name, uint32_t width, uint32_t spp) {
  char path[256];
  snprintf(path, sizeof path, "samples/%s/%s.gltf", name, name);
  pb_scene s;
  pb_load_desc ld = {0};
  pb_result r = pb_scene_load(path, &ld, &s);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return;
  uint32_t w, h;
  pb_camera_image_size(&s.cameras[0], width, 0, &w, &h);
  pb_gpu_scene gs;
  pb_render_result gr;
  pb_ref_result rr;
  memset(&rr, 0, sizeof rr);
  memset(&gr, 0, sizeof gr);
  r = pb_gpu_scene_create(g, &s, &gs);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) goto out;
  pb_render_desc rd = {.spp = spp, .direct_only = 1, .seed = 1};
  r = pb_render_frame(g, &s, &gs, 0, w, h, &rd, &gr);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) fprintf(stderr, "%s: %s\n", name, pb_error_message());
  pb_ref_desc fd = {.spp = spp, .max_bounces = 1, .seed = 2, .mode = PB_REF_MODE_PT};
  pb_result r2 = pb_ref_render(&s, 0, w, h, &fd, &rr);
  CHECK_EQ_INT(r2, PB_OK);
  if (r == PB_OK && r2 == PB_OK) {
    pb_metrics m;
    r = pb_metrics_compute(gr.direct, rr.direct, w, h, 3, NULL, &m);
    CHECK_EQ_INT(r, PB_OK);
    printf("%-14s %ux%u, %u spp: direct AOV vs reference: relMSE %.3g (threshold 1e-3), RMSE %.3g, PSNR %.1f dB, "
           "GPU gbuffer %.1f ms + direct %.1f ms\n",
           name, w, h, spp, m.relmse, m.rmse, m.psnr, gr.stats.gbuffer_ms, gr.stats.direct_ms);
    CHECK(m.relmse < 1e-3);
    CHECK_EQ_INT(m.nonfinite, 0);
  }
out:
  pb_ref_result_destroy(&rr);
  pb_render_result_destroy(&gr);
  pb_gpu_scene_destroy(g, &gs);
  pb_scene_destroy(&s);
  pb_error_clear();
}

/* A 2 x 2 m plane (two triangles, albedo 0.8, no specular layer) at y = 0,
 * a point light of I = 10 W/sr 1 m above its centre, camera looking down
 * from 3 m: the centre pixel is rho/pi * I / d^2 (cos = 1, d = 1). */
static void analytic(pb_gpu *g) {
  float pos[4][3] = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}};
  float nrm[4][3] = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  float uv[4][2] = {{0, 0}};
  uint32_t tri[2][3] = {{0, 2, 1}, {0, 3, 2}};
  uint32_t tm[2] = {0, 0};
  pb_material mat;
  memset(&mat, 0, sizeof mat);
  mat.base_color[0] = mat.base_color[1] = mat.base_color[2] = 0.8f;
  mat.base_color[3] = 1;
  mat.base_color_tex = mat.metallic_roughness_tex = mat.emissive_tex = mat.normal_tex = PB_NO_TEXTURE;
  mat.roughness = 1;
  mat.specular = 0; /* no specular layer at all: pure Lambert */
  mat.ior = 1.5f;
  pb_light light;
  memset(&light, 0, sizeof light);
  light.type = PB_LIGHT_POINT;
  light.position[1] = 1;
  light.color[0] = light.color[1] = light.color[2] = 1;
  light.intensity = 10;
  pb_camera cam;
  memset(&cam, 0, sizeof cam);
  cam.position[1] = 3;
  cam.forward[1] = -1;
  cam.up[2] = -1;
  cam.right[0] = 1;
  cam.yfov = 0.5f;
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
  s.materials = &mat;
  s.material_count = 1;
  s.lights = &light;
  s.light_count = 1;
  s.cameras = &cam;
  s.camera_count = 1;
  pb_scene_finalize(&s);
  pb_gpu_scene gs;
  pb_render_result res;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &s, &gs), PB_OK);
  pb_render_desc rd = {.direct_only = 1};
  pb_result r = pb_render_frame(g, &s, &gs, 0, 33, 33, &rd, &res);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK) {
    const float *c = &res.direct[3 * (16 * 33 + 16)];
    double want = 0.8 / M_PI * 10.0;
    printf("analytic plane: centre %.6f, expected %.6f\n", c[0], want);
    CHECK_NEAR(c[0], want, 1e-4 * want);
    CHECK_NEAR(c[1], want, 1e-4 * want);
    /* An off-centre pixel: cos^3 / d^2 falloff, within the pixel footprint. */
    pb_render_result_destroy(&res);
  }
  pb_gpu_scene_destroy(g, &gs);
}

/* Emissive triangles (next-event estimation toward emitters picked by power)
 * against the reference's direct AOV, which combines light and BSDF samples
 * with MIS: the same expectation (see shaders/scene/direct.comp). A room corner
 * (floor and back wall, Lambert 0.8), a glossy square (GGX, roughness 0.5)
 * that casts a soft shadow, a 1 x 1 m single-sided emitter facing down (seen
 * from below by the camera, so its front is in the image) and a small
 * double-sided vertical emitter of another colour (both sides light the
 * room). No point lights: only emitters light it. 64 x 48, 1024 spp. */
static void add_quad(float (*pos)[3], uint32_t (*tri)[3], uint32_t *tm, uint32_t *nv, uint32_t *nt,
                     const float q[4][3], uint32_t mat) {
  uint32_t b = *nv;
  for (int i = 0; i < 4; ++i) memcpy(pos[b + i], q[i], sizeof pos[0]);
  *nv += 4;
  tri[*nt][0] = b, tri[*nt][1] = b + 1, tri[*nt][2] = b + 2;
  tm[(*nt)++] = mat;
  tri[*nt][0] = b, tri[*nt][1] = b + 2, tri[*nt][2] = b + 3;
  tm[(*nt)++] = mat;
}

static void emissive_quad(pb_gpu *g) {
  float pos[20][3];
  float uv[20][2];
  uint32_t tri[10][3], tm[10], nv = 0, nt = 0;
  memset(uv, 0, sizeof uv);
  /* Counter-clockwise seen from the side the normal points to. */
  const float floor_q[4][3] = {{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}};        /* +y */
  const float wall_q[4][3] = {{-2, 0, -2}, {2, 0, -2}, {2, 2.5f, -2}, {-2, 2.5f, -2}}; /* +z */
  const float box_q[4][3] = {{-0.4f, 0.6f, -0.4f}, {-0.4f, 0.6f, 0.4f}, {0.4f, 0.6f, 0.4f}, {0.4f, 0.6f, -0.4f}};
  const float lamp_q[4][3] = {{-0.5f, 1.6f, -0.5f}, {0.5f, 1.6f, -0.5f}, {0.5f, 1.6f, 0.5f}, {-0.5f, 1.6f, 0.5f}}; /* -y */
  const float side_q[4][3] = {{1.5f, 0.2f, -0.3f}, {1.5f, 0.2f, 0.3f}, {1.5f, 0.9f, 0.3f}, {1.5f, 0.9f, -0.3f}};
  add_quad(pos, tri, tm, &nv, &nt, floor_q, 0);
  add_quad(pos, tri, tm, &nv, &nt, wall_q, 0);
  add_quad(pos, tri, tm, &nv, &nt, box_q, 1);
  add_quad(pos, tri, tm, &nv, &nt, lamp_q, 2);
  add_quad(pos, tri, tm, &nv, &nt, side_q, 3);
  pb_material mat[4];
  memset(mat, 0, sizeof mat);
  for (int i = 0; i < 4; ++i) {
    mat[i].base_color[0] = mat[i].base_color[1] = mat[i].base_color[2] = 0.8f;
    mat[i].base_color[3] = 1;
    mat[i].base_color_tex = mat[i].metallic_roughness_tex = mat[i].emissive_tex = mat[i].normal_tex = PB_NO_TEXTURE;
    mat[i].roughness = 1;
    mat[i].ior = 1.5f;
  }
  mat[1].base_color[0] = 0.9f, mat[1].base_color[1] = 0.6f, mat[1].base_color[2] = 0.3f;
  mat[1].roughness = 0.5f;
  mat[1].specular = 1;
  mat[1].specular_color[0] = mat[1].specular_color[1] = mat[1].specular_color[2] = 1;
  mat[2].base_color[0] = mat[2].base_color[1] = mat[2].base_color[2] = 0.2f;
  mat[2].emissive[0] = 5, mat[2].emissive[1] = 4, mat[2].emissive[2] = 3;
  mat[3].emissive[0] = 1, mat[3].emissive[1] = 2, mat[3].emissive[2] = 4;
  mat[3].double_sided = 1;
  pb_camera cam;
  memset(&cam, 0, sizeof cam);
  float fy = -0.6f, fz = -3.8f, fl = sqrtf(fy * fy + fz * fz);
  cam.position[1] = 1.1f, cam.position[2] = 3.8f;
  cam.forward[1] = fy / fl, cam.forward[2] = fz / fl;
  cam.right[0] = 1;
  cam.up[1] = -fz / fl, cam.up[2] = fy / fl;
  cam.yfov = 0.9f;
  cam.aspect = 4.0f / 3.0f;
  pb_scene s;
  memset(&s, 0, sizeof s);
  s.positions = pos;
  s.uvs = uv;
  s.vertex_count = nv;
  s.triangles = tri;
  s.triangle_material = tm;
  s.triangle_count = nt;
  s.materials = mat;
  s.material_count = 4;
  s.cameras = &cam;
  s.camera_count = 1;
  pb_scene_finalize(&s);
  CHECK(s.features & PB_FEATURE_EMISSIVE);
  const uint32_t w = 64, h = 48, spp = 1024;
  pb_gpu_scene gs;
  pb_render_result gr;
  pb_ref_result rr;
  memset(&gr, 0, sizeof gr);
  memset(&rr, 0, sizeof rr);
  pb_result r = pb_gpu_scene_create(g, &s, &gs);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) return;
  CHECK_EQ_INT(gs.emitter_count, 4);
  pb_render_desc rd = {.spp = spp, .direct_only = 1, .seed = 3};
  r = pb_render_frame(g, &s, &gs, 0, w, h, &rd, &gr);
  CHECK_EQ_INT(r, PB_OK);
  pb_ref_desc fd = {.spp = spp, .max_bounces = 1, .seed = 4, .mode = PB_REF_MODE_PT};
  pb_result r2 = pb_ref_render(&s, 0, w, h, &fd, &rr);
  CHECK_EQ_INT(r2, PB_OK);
  if (r == PB_OK && r2 == PB_OK) {
    pb_metrics m;
    CHECK_EQ_INT(pb_metrics_compute(gr.direct, rr.direct, w, h, 3, NULL, &m), PB_OK);
    double gm = 0, rm = 0;
    for (size_t i = 0; i < (size_t)3 * w * h; ++i) gm += gr.direct[i], rm += rr.direct[i];
    printf("emissive quad  %ux%u, %u spp: direct AOV vs reference: relMSE %.3g (threshold 1e-3), RMSE %.3g, "
           "mean %.5f vs %.5f, GPU gbuffer %.1f ms + direct %.1f ms\n",
           w, h, spp, m.relmse, m.rmse, gm / (3.0 * w * h), rm / (3.0 * w * h), gr.stats.gbuffer_ms,
           gr.stats.direct_ms);
    CHECK(m.relmse < 1e-3);
    CHECK_EQ_INT(m.nonfinite, 0);
    CHECK(fabs(gm - rm) < 5e-3 * rm);
  }
  pb_ref_result_destroy(&rr);
  pb_render_result_destroy(&gr);
  pb_gpu_scene_destroy(g, &gs);
  pb_error_clear();
}

/* Mirror and glass chains render finite images with light in them. */
static void specular(pb_gpu *g, const char *name) {
  char path[256];
  snprintf(path, sizeof path, "samples/%s/%s.gltf", name, name);
  pb_scene s;
  pb_load_desc ld = {0};
  if (pb_scene_load(path, &ld, &s) != PB_OK) {
    CHECK(0);
    return;
  }
  pb_gpu_scene gs;
  pb_render_result res;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &s, &gs), PB_OK);
  pb_render_desc rd = {.spp = 4, .max_specular_depth = 8};
  pb_result r = pb_render_frame(g, &s, &gs, 0, 64, 0 + 64 * 9 / 16 + 28 * (s.cameras[0].aspect < 1.5f), &rd, &res);
  CHECK_EQ_INT(r, PB_OK);
  if (r == PB_OK) {
    size_t n = (size_t)res.width * res.height, bad = 0;
    double sum = 0;
    for (size_t i = 0; i < 4 * n; ++i) {
      if (!isfinite(res.beauty[i]) || res.beauty[i] < 0) bad++;
      else if (i % 4 != 3) sum += res.beauty[i];
    }
    printf("%-14s specular chains: mean beauty %.4f, %zu non-finite/negative values\n", name, sum / (3.0 * n), bad);
    CHECK_EQ_INT(bad, 0);
    CHECK(sum > 0);
    pb_render_result_destroy(&res);
  }
  pb_gpu_scene_destroy(g, &gs);
  pb_scene_destroy(&s);
}

int main(void) {
  PBT_GPU_OPEN(g);
  analytic(g);
  emissive_quad(g);
  compare_scene(g, "cornell_box", 96, 64);
  compare_scene(g, "spot_room", 128, 64);
  compare_scene(g, "sun_atrium", 128, 64);
  specular(g, "ring");
  specular(g, "cornell_caustics");
  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_destroy(g);
  return pbt_done();
}
