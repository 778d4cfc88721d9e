/* The GPU's camera rays (shaders/common/camera.glsl) against the host's
 * (scene/camera.c), and crops against the full frame: every pixel's depth
 * on a plane equals the host ray's, for a perspective camera with Blender's
 * AUTO fit, a lens shift and a near clip plane that cuts the picture, and
 * for an orthographic camera, and for panoramic ones (equirectangular with
 * ranges and a shift, fisheye equisolid, mirror ball: the depth is the
 * distance); a crop of the frame (render --crop) has the
 * full render's pixels exactly (same seed, 4 jittered samples, an emissive
 * triangle sampled per pixel); the far clip plane hides what lies beyond. */
#include <math.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "render/render.h"
#include "scene/camera.h"
#include "test_ref_scene.h"

enum { W = 48, H = 32 };

/* Distance along the ray to the square |x|, |y| <= h in the plane z = z0,
 * or -1. */
static double hit_square(const float o[3], const float d[3], double z0, double h) {
  if (d[2] == 0) return -1;
  double t = (z0 - o[2]) / d[2], x = o[0] + t * d[0], y = o[1] + t * d[1];
  return t >= 0 && fabs(x) <= h && fabs(y) <= h ? t : -1;
}

/* Depth along forward of the first hit of the host ray through pixel
 * (x, y)'s centre (the floor z = 0, half-size 4, or the emitter z = 1.5,
 * half-size 0.3), 0 when it misses or the hit is beyond the far plane. */
static double host_depth(const pb_gpu_camera *v, uint32_t x, uint32_t y) {
  float o[3], d[3], t0, tmax;
  if (!pb_camera_ray_lens(v, x + 0.5f, y + 0.5f, NULL, o, d, &t0, &tmax)) return 0;
  double t = hit_square(o, d, 0.0, 4.0), te = hit_square(o, d, 1.5, 0.3);
  if (te >= 0 && (t < 0 || te < t)) t = te;
  if (t < 0 || t > tmax) return 0;
  if (v->projection) return t0 + t; /* a panorama's depth: the distance */
  double cz = d[0] * v->forward[0] + d[1] * v->forward[1] + d[2] * v->forward[2];
  return (t0 + t) * cz;
}

/* The GPU's depth AOV matches the host's rays at every pixel; returns the
 * count of pixels that see the plane. */
static int check_depths(pb_gpu *g, pb_scene *s, const pb_gpu_scene *gs, const char *what) {
  pb_render_desc rd = {.direct_only = 1};
  pb_render_result res;
  CHECK_EQ_INT(pb_render_frame(g, s, gs, 0, W, H, &rd, &res), PB_OK);
  pb_gpu_camera v;
  pb_camera_view(&s->cameras[0], W, H, &v);
  int seen = 0, bad = 0;
  double worst = 0;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x) {
      double want = host_depth(&v, x, y), got = res.depth ? res.depth[y * W + x] : -1;
      /* A ray through an edge of a square may fall either way in float:
       * allow a handful. */
      if ((want > 0) != (got > 0)) {
        bad++;
        continue;
      }
      if (want > 0) {
        seen++;
        double e = fabs(got - want) / want;
        if (e > worst) worst = e;
      }
    }
  printf("%s: %d pixels see geometry, %d disagree on hit/miss, worst depth error %.2e\n", what, seen, bad, worst);
  CHECK(bad <= 2);
  CHECK(worst < 1e-4);
  pb_render_result_destroy(&res);
  return seen;
}

int main(void) {
  PBT_GPU_OPEN(g);
  pb_scene s;
  tsc_init(&s);
  uint32_t m = tsc_material(&s, tsc_lambert(0.8f, 0.8f, 0.8f));
  tsc_floor(&s, 4.0f, 0.0f, m);
  /* A small emissive square above the floor, facing down (sampled per pixel
   * with the pixel's random numbers), and a point light. */
  pb_material e = tsc_lambert(0, 0, 0);
  e.emissive[0] = e.emissive[1] = e.emissive[2] = 5.0f;
  uint32_t me = tsc_material(&s, e);
  float a[3] = {-0.3f, -0.3f, 1.5f}, b[3] = {-0.3f, 0.3f, 1.5f}, c[3] = {0.3f, 0.3f, 1.5f}, d[3] = {0.3f, -0.3f, 1.5f};
  tsc_quad(&s, a, b, c, d, me);
  pb_light *l = tsc_light(&s, PB_LIGHT_POINT);
  l->position[0] = 1, l->position[2] = 2;
  l->intensity = 3;
  float pos[3] = {0.5f, -2.0f, 3.0f}, fwd[3] = {-0.1f, 0.6f, -1.0f}, up[3] = {0, 0, 1};
  tsc_camera(&s, pos, fwd, up, 50.0f);
  pb_camera *cam = &s.cameras[0];
  cam->fit = PB_CAMERA_FIT_AUTO;
  cam->yfov = 2.0f * atanf(18.0f / 35.0f); /* Blender: 35 mm lens, 36 mm sensor */
  cam->shift[0] = 0.2f, cam->shift[1] = -0.15f;
  cam->znear = 3.2f;                        /* cuts the near part of the floor */
  pb_scene_finalize(&s);
  pb_gpu_scene gs;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &s, &gs), PB_OK);

  int seen = check_depths(g, &s, &gs, "perspective, AUTO fit, shift, near clip");
  CHECK(seen > W * H / 4 && seen < W * H); /* the near plane cut some of it */

  /* A crop equals the full frame there, pixel for pixel, all AOVs. */
  pb_render_desc full = {.spp = 4, .seed = 7};
  pb_render_desc part = full;
  part.full_width = W, part.full_height = H, part.crop_x = 13, part.crop_y = 9;
  pb_render_result rf, rc;
  CHECK_EQ_INT(pb_render_frame(g, &s, &gs, 0, W, H, &full, &rf), PB_OK);
  CHECK_EQ_INT(pb_render_frame(g, &s, &gs, 0, 20, 15, &part, &rc), PB_OK);
  double diff = 0, sum = 0;
  for (uint32_t y = 0; y < 15; ++y)
    for (uint32_t x = 0; x < 20; ++x)
      for (int k = 0; k < 4; ++k) {
        float f = rf.beauty[4 * ((y + 9) * W + x + 13) + k], p = rc.beauty[4 * (y * 20 + x) + k];
        diff = fmax(diff, fabs(f - p));
        sum += f;
      }
  printf("crop 20x15 at (13, 9) vs the full frame: largest difference %.3g (mean beauty %.4g)\n", diff,
         sum / (20 * 15 * 4));
  CHECK(sum > 0);
  CHECK(diff == 0);
  pb_render_result_destroy(&rf);
  pb_render_result_destroy(&rc);
  /* A crop that leaves the frame is refused. */
  part.crop_x = 40;
  CHECK_EQ_INT(pb_render_frame(g, &s, &gs, 0, 20, 15, &part, &rc), PB_ERR_USAGE);
  pb_error_clear();

  /* Orthographic, HORIZONTAL fit, shifted, with a far plane that cuts the
   * floor's far part. */
  cam->orthographic = 1;
  cam->fit = PB_CAMERA_FIT_HORIZONTAL;
  cam->ortho_size = 5.0f;
  cam->znear = 0.5f;
  cam->zfar = 4.5f;
  seen = check_depths(g, &s, &gs, "orthographic, horizontal fit, shift, far clip");
  CHECK(seen > W * H / 8 && seen < W * H);

  /* Panoramas (Cycles' equirectangular with narrowed ranges, fisheye
   * equisolid, mirror ball): the GPU's rays are the host's, pixels outside
   * a fisheye's circle see nothing. */
  cam->orthographic = 0;
  cam->fit = PB_CAMERA_FIT_AUTO;
  cam->znear = 0.1f;
  cam->zfar = 0.0f;
  cam->shift[0] = 0.05f, cam->shift[1] = 0.0f;
  cam->panorama = PB_CAMERA_PANO_EQUIRECTANGULAR;
  cam->latitude[0] = -1.2f, cam->latitude[1] = 0.9f;
  cam->longitude[0] = -2.5f, cam->longitude[1] = 2.0f;
  seen = check_depths(g, &s, &gs, "equirectangular, ranges, shift");
  CHECK(seen > W * H / 8 && seen < W * H);
  cam->shift[0] = 0.0f;
  cam->panorama = PB_CAMERA_PANO_FISHEYE_EQUISOLID;
  cam->fisheye_lens = 8.0f, cam->fisheye_fov = 3.0f, cam->sensor[0] = 36.0f, cam->sensor[1] = 24.0f;
  seen = check_depths(g, &s, &gs, "fisheye equisolid");
  CHECK(seen > W * H / 8 && seen < W * H);
  cam->panorama = PB_CAMERA_PANO_MIRRORBALL;
  seen = check_depths(g, &s, &gs, "mirror ball");
  CHECK(seen > W * H / 8 && seen < W * H);

  CHECK_EQ_INT(pb_gpu_validation_errors(g), 0);
  pb_gpu_scene_destroy(g, &gs);
  pb_scene_destroy(&s);
  pb_gpu_destroy(g);
  return pbt_done();
}
