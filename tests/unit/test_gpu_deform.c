/* Skinned and morphed geometry in the GPU pipeline, on Blender's own scene
 * (tests/data/deform: a cylinder skinned to three bending bones, a cube with
 * two animated shape keys; Blender also baked it at frames 12 and 24):
 *  - the GPU scene made at frame 0 and updated to frame 12, then 24 (BVH
 *    refit or rebuild, pb_gpu_scene_update), renders what the baked scene
 *    renders: the direct light of 99.5 % of the pixels within 1e-4 of the
 *    peak, in the GPU pipeline and in the reference (fresh Embree scenes);
 *    both scenes carry the baked file's normals (positions are what differ:
 *    test_deform_blender), so only the posed geometry is compared;
 *  - the motion vectors from frame 12 to 24 follow the deformation: on
 *    every pixel whose centre sees the cylinder or the cube, the vector is
 *    the projection of the same triangle point on its frame-12 vertices
 *    (host arithmetic, motion.h pb_camera_project) within 1e-3 px;
 *  - the temporal filter leaves no ghost where the deformation moved: with
 *    an indirect image of 3 on the deforming meshes and 1 elsewhere,
 *    filtered over frames 12 (history) and 24, every pixel the meshes
 *    uncovered restarts at 1 exactly, and most pixels still on them keep
 *    their history.
 * Validation layers on; exit 77 without a device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "ref/ref.h"
#include "render/scene/motion.h"
#include "render/render.h"
#include "render/filter/temporal.h"

enum { W = 64, H = 48, N = W * H };

static int load(const char *path, pb_scene *s) {
  pb_result r = pb_scene_load(path, NULL, s);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  CHECK_EQ_INT(r, PB_OK);
  return r == PB_OK;
}

/* Fraction of channels of a and b equal within tol x the peak of b. */
static double agree(const float *a, const float *b, size_t n, double tol, double *peak_out, double *worst) {
  double peak = 0;
  for (size_t i = 0; i < n; ++i) peak = fmax(peak, b[i]);
  size_t ok = 0;
  *worst = 0;
  for (size_t i = 0; i < n; ++i) {
    double e = fabs(a[i] - b[i]);
    *worst = fmax(*worst, e);
    ok += e <= tol * peak;
  }
  *peak_out = peak;
  return (double)ok / (double)n;
}

static void pixels(pb_gpu *g) {
  pb_scene anim;
  if (!load("tests/data/deform/deform.gltf", &anim)) return;
  pb_gpu_scene gs;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &anim, &gs), PB_OK); /* the file's own pose: frame 0 */
  for (int f = 12; f <= 24; f += 12) {
    char path[128];
    snprintf(path, sizeof path, "tests/data/deform/deform_baked_f%02d.gltf", f);
    pb_scene baked;
    if (!load(path, &baked)) break;
    CHECK_EQ_INT(pb_scene_set_time(&anim, f / 24.0), PB_OK);
    memcpy(anim.normals, baked.normals, (size_t)anim.vertex_count * sizeof *anim.normals);
    double ms;
    CHECK_EQ_INT(pb_gpu_scene_update(g, &anim, &gs, PB_BVH_UPDATE_AUTO, &ms), PB_OK);
    pb_gpu_scene gb;
    CHECK_EQ_INT(pb_gpu_scene_create(g, &baked, &gb), PB_OK);
    pb_render_desc rd = {.direct_only = 1};
    pb_render_result ra, rb;
    memset(&ra, 0, sizeof ra);
    memset(&rb, 0, sizeof rb);
    pb_result r1 = pb_render_frame(g, &anim, &gs, 0, W, H, &rd, &ra), r2 = pb_render_frame(g, &baked, &gb, 0, W, H, &rd, &rb);
    CHECK_EQ_INT(r1, PB_OK);
    CHECK_EQ_INT(r2, PB_OK);
    pb_ref_desc fd = {.spp = 4, .max_bounces = 1, .seed = 3, .mode = PB_REF_MODE_PT, .threads = 2};
    pb_ref_result fa, fb;
    memset(&fa, 0, sizeof fa);
    memset(&fb, 0, sizeof fb);
    pb_result r3 = pb_ref_render(&anim, 0, W, H, &fd, &fa), r4 = pb_ref_render(&baked, 0, W, H, &fd, &fb);
    CHECK_EQ_INT(r3, PB_OK);
    CHECK_EQ_INT(r4, PB_OK);
    if (r1 == PB_OK && r2 == PB_OK && r3 == PB_OK && r4 == PB_OK) {
      double pg, pr, wg, wr;
      double ag = agree(ra.direct, rb.direct, (size_t)N * 3, 1e-4, &pg, &wg);
      double ar = agree(fa.direct, fb.direct, (size_t)N * 3, 1e-4, &pr, &wr);
      printf("frame %d, %dx%d direct light, posed (GPU scene updated from frame 0 in %.2f ms) against Blender's bake: "
             "channels within 1e-4 of the peak: GPU %.2f %% (worst %.3g of %.3g), reference %.2f %% (worst %.3g)\n",
             f, W, H, ms, 100 * ag, wg, pg, 100 * ar, wr);
      CHECK(pg > 0.1);
      CHECK(ag >= 0.995);
      CHECK(ar >= 0.995);
    }
    pb_render_result_destroy(&ra);
    pb_render_result_destroy(&rb);
    pb_ref_result_destroy(&fa);
    pb_ref_result_destroy(&fb);
    pb_gpu_scene_destroy(g, &gb);
    pb_scene_destroy(&baked);
  }
  pb_gpu_scene_destroy(g, &gs);
  pb_scene_destroy(&anim);
}

/* Which material index the skinned and morphed instances use: every
 * triangle of a deformed range (skin or targets). */
static uint8_t *deformed_triangles(const pb_scene *s, const float (*rest)[3], const float (*posed)[3]) {
  uint8_t *d = calloc(s->triangle_count + 1, 1);
  for (uint32_t t = 0; d && t < s->triangle_count; ++t)
    for (int c = 0; c < 3; ++c)
      if (memcmp(rest[s->triangles[t][c]], posed[s->triangles[t][c]], sizeof rest[0])) d[t] = 1;
  return d;
}

static void motion_and_ghosts(pb_gpu *g) {
  pb_scene s;
  if (!load("tests/data/deform/deform.gltf", &s)) return;
  size_t pbytes = (size_t)s.vertex_count * sizeof *s.positions;
  float(*p12)[3] = malloc(pbytes);
  CHECK_EQ_INT(pb_scene_set_time(&s, 0.5), PB_OK);
  memcpy(p12, s.positions, pbytes);
  pb_gpu_scene gs;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &s, &gs), PB_OK);
  pb_render_desc rd = {.direct_only = 1};
  pb_render_result a, b;
  memset(&a, 0, sizeof a);
  memset(&b, 0, sizeof b);
  CHECK_EQ_INT(pb_render_frame(g, &s, &gs, 0, W, H, &rd, &a), PB_OK);
  CHECK_EQ_INT(pb_scene_set_time(&s, 1.0), PB_OK);
  CHECK_EQ_INT(pb_gpu_scene_update(g, &s, &gs, PB_BVH_UPDATE_AUTO, NULL), PB_OK);
  CHECK_EQ_INT(pb_render_frame(g, &s, &gs, 0, W, H, &rd, &b), PB_OK);
  uint8_t *moved = deformed_triangles(&s, (const float(*)[3])p12, (const float(*)[3])s.positions);
  static float motion[4 * N];
  const pb_camera *cam = &s.cameras[0];
  CHECK_EQ_INT(pb_motion_vectors(g, &s, &gs, (const float(*)[3])p12, cam, cam, W, H, motion, NULL), PB_OK);

  /* Motion vectors against the host's projection of each pixel's hit. */
  static pb_gpu_ray rays[N];
  static pb_gpu_hit hits[N];
  pb_camera_primary_rays(cam, W, H, 0, N, rays);
  pb_raycast_pass rc;
  CHECK_EQ_INT(pb_raycast_create(g, &gs, N, &rc), PB_OK);
  CHECK_EQ_INT(pb_raycast_run(g, &rc, rays, N, 0, hits, NULL), PB_OK);
  pb_raycast_destroy(g, &rc);
  int on = 0, bad = 0, big = 0;
  double worst = 0;
  for (int p = 0; p < N && moved; ++p) {
    if (hits[p].prim == PB_GPU_MISS || !moved[hits[p].prim]) continue;
    const uint32_t *t = s.triangles[hits[p].prim];
    float u = hits[p].u, v = hits[p].v, w = 1 - u - v, q[3], x, y, z;
    for (int k = 0; k < 3; ++k) q[k] = p12[t[0]][k] * w + p12[t[1]][k] * u + p12[t[2]][k] * v;
    on++;
    if (!pb_camera_project(cam, W, H, q, &x, &y, &z)) continue;
    double dx = x - ((p % W) + 0.5), dy = y - ((p / W) + 0.5);
    double e = fmax(fabs(motion[4 * p] - dx), fabs(motion[4 * p + 1] - dy));
    worst = fmax(worst, e);
    bad += motion[4 * p + 3] != 1.0f || e > 1e-3;
    big += fabs(dx) + fabs(dy) > 1.0;
  }
  printf("motion vectors frame 12 -> 24: %d pixels on the deforming meshes (%d moved more than a pixel), worst "
         "difference to the host's projection %.2g px, %d wrong\n",
         on, big, worst, bad);
  CHECK(on > 100 && big > 50);
  CHECK_EQ_INT(bad, 0);

  /* The temporal filter: 3 on the deforming meshes, 1 elsewhere. */
  pb_temporal *tf = NULL;
  CHECK_EQ_INT(pb_temporal_create(g, W, H, NULL, &tf), PB_OK);
  static float ind[3 * N], hist[N];
  uint32_t skin_mat = 0; /* the cylinder's "Skin" material: 0 in the file */
  CHECK(strcmp(s.materials[skin_mat].name, "Skin") == 0);
  for (int it = 0; it < 3 && tf; ++it) {
    for (int p = 0; p < N; ++p)
      for (int k = 0; k < 3; ++k) ind[3 * p + k] = a.material[p] == skin_mat + 1 ? 3.0f : 1.0f;
    CHECK_EQ_INT(pb_temporal_apply(g, tf, a.normal, a.depth, a.albedo, NULL, 1, ind, hist, NULL), PB_OK);
  }
  int uncovered = 0, ghost = 0, stayed = 0, kept = 0;
  if (tf) {
    for (int p = 0; p < N; ++p)
      for (int k = 0; k < 3; ++k) ind[3 * p + k] = b.material[p] == skin_mat + 1 ? 3.0f : 1.0f;
    CHECK_EQ_INT(pb_temporal_apply(g, tf, b.normal, b.depth, b.albedo, motion, 0, ind, hist, NULL), PB_OK);
    for (int p = 0; p < N; ++p) {
      int was = a.material[p] == skin_mat + 1, is = b.material[p] == skin_mat + 1;
      if (was && !is && b.material[p] > 0) {
        uncovered++;
        if (hist[p] != 1.0f || fabsf(ind[3 * p] - 1.0f) > 1e-6f) ghost++;
      } else if (was && is) {
        stayed++;
        kept += hist[p] > 1.5f;
      }
    }
  }
  printf("temporal filter over the deformation: %d pixels uncovered, %d with a ghost; %d stayed on the cylinder, %d "
         "of them kept their history\n",
         uncovered, ghost, stayed, kept);
  CHECK(uncovered > 20);
  CHECK_EQ_INT(ghost, 0);
  CHECK(kept > stayed / 2);
  pb_temporal_destroy(g, tf);
  free(moved);
  free(p12);
  pb_render_result_destroy(&a);
  pb_render_result_destroy(&b);
  pb_gpu_scene_destroy(g, &gs);
  pb_scene_destroy(&s);
}

int main(void) {
  PBT_GPU_OPEN(g);
  pixels(g);
  motion_and_ghosts(g);
  pb_gpu_destroy(g);
  return pbt_done();
}
