/* The camera model (scene/camera.h), GPU-free: the window of a glTF camera
 * is the one every renderer had before (tan of half yfov, aspect from the
 * image); Blender's sensor fit, lens shift, orthographic scale and clip
 * planes; a crop sees exactly the full frame's rays; projection inverts the
 * ray (crops offset the pixel position: render --crop); the PHOTONBRIDGE_blender camera extension's values and errors. */
#include <math.h>
#include <string.h>

#include "core/result.h"
#include "pbtest.h"
#include "scene/camera.h"

static pb_camera base(void) {
  pb_camera c;
  memset(&c, 0, sizeof c);
  c.forward[2] = -1;
  c.up[1] = 1;
  c.right[0] = 1;
  c.position[0] = 1, c.position[1] = 2, c.position[2] = 3;
  return c;
}

/* The screen point of image position (px, py) of view v. */
static void screen(const pb_gpu_camera *v, double px, double py, double *sx, double *sy) {
  *sx = v->x0 + px * v->dx;
  *sy = v->y0 + py * v->dy;
}

static pb_gltf_camera blender_cam(const char *type, const char *fit) {
  pb_gltf_camera g;
  memset(&g, 0, sizeof g);
  g.type = "perspective";
  g.perspective = 1;
  g.yfov = 0.5;
  g.znear = 0.1;
  g.zfar = 100;
  g.aspect_ratio = 1.5;
  g.blender.present = 1;
  g.blender.type = type;
  g.blender.sensor_fit = fit;
  double *n[] = {&g.blender.lens, &g.blender.sensor_width, &g.blender.sensor_height, &g.blender.ortho_scale,
                 &g.blender.shift_x, &g.blender.shift_y, &g.blender.clip_start, &g.blender.clip_end,
                 &g.blender.aspect};
  for (size_t i = 0; i < sizeof n / sizeof *n; ++i) *n[i] = NAN;
  return g;
}

int main(void) {
  /* glTF perspective: half-extents tan(yfov/2) vertically, x aspect. */
  pb_camera c = base();
  c.yfov = 0.8f;
  pb_gpu_camera v;
  pb_camera_view(&c, 200, 100, &v);
  double ty = tan(0.4), sx, sy;
  screen(&v, 0, 0, &sx, &sy);
  CHECK_NEAR(sx, -2 * ty, 1e-6);
  CHECK_NEAR(sy, ty, 1e-6);
  screen(&v, 200, 100, &sx, &sy);
  CHECK_NEAR(sx, 2 * ty, 1e-6);
  CHECK_NEAR(sy, -ty, 1e-6);
  CHECK_EQ_INT(v.orthographic, 0);

  /* Blender's AUTO fit spans the larger side: the landscape image's width,
   * the portrait one's height; HORIZONTAL always the width. */
  c.fit = PB_CAMERA_FIT_AUTO;
  pb_camera_view(&c, 200, 100, &v);
  CHECK_NEAR(v.dx * 200.0, 2 * ty, 1e-6);
  pb_camera_view(&c, 100, 200, &v);
  CHECK_NEAR(-v.dy * 200.0, 2 * ty, 1e-6);
  CHECK_NEAR(v.dx * 100.0, ty, 1e-6);
  c.fit = PB_CAMERA_FIT_HORIZONTAL;
  pb_camera_view(&c, 100, 200, &v);
  CHECK_NEAR(v.dx * 100.0, 2 * ty, 1e-6);

  /* Lens shift: the window's centre moves by shift x the fitted extent. */
  c.fit = PB_CAMERA_FIT_AUTO;
  c.shift[0] = 0.25f, c.shift[1] = -0.1f;
  pb_camera_view(&c, 200, 100, &v);
  screen(&v, 100, 50, &sx, &sy);
  CHECK_NEAR(sx, 0.25 * 2 * ty, 1e-6);
  CHECK_NEAR(sy, -0.1 * 2 * ty, 1e-6);

  c.znear = 0.5f, c.zfar = 20.0f;
  pb_camera_view(&c, 200, 100, &v);
  float o1[3], d1[3], t01, tm1;
  pb_camera_ray(&v, 37 + 5.5f, 11 + 7.25f, o1, d1, &t01, &tm1);
  /* Clip planes are planes: the origin lies at depth znear, the end at zfar. */
  double z_org = (o1[0] - c.position[0]) * c.forward[0] + (o1[1] - c.position[1]) * c.forward[1] +
                 (o1[2] - c.position[2]) * c.forward[2];
  CHECK_NEAR(z_org, 0.5, 1e-5);
  double cz = d1[0] * c.forward[0] + d1[1] * c.forward[1] + d1[2] * c.forward[2];
  CHECK_NEAR((t01 + tm1) * cz, 20.0, 1e-4);
  /* Projection inverts the ray. */
  float p[3], x, y, z;
  for (int k = 0; k < 3; ++k) p[k] = o1[k] + 3.0f * d1[k];
  CHECK(pb_camera_view_project(&v, p, &x, &y, &z));
  CHECK_NEAR(x, 37 + 5.5, 1e-3);
  CHECK_NEAR(y, 11 + 7.25, 1e-3);
  CHECK_NEAR(z, (t01 + 3.0) * cz, 1e-4);
  float behind[3] = {c.position[0], c.position[1], c.position[2] + 1.0f};
  CHECK(!pb_camera_view_project(&v, behind, &x, &y, &z));

  /* Orthographic: parallel rays along forward from the camera plane, the
   * fitted side ortho_size metres across. */
  pb_camera o = base();
  o.orthographic = 1;
  o.fit = PB_CAMERA_FIT_AUTO;
  o.ortho_size = 4.0f;
  o.znear = 0.25f;
  pb_camera_view(&o, 100, 50, &v);
  pb_camera_ray(&v, 0, 0, o1, d1, &t01, &tm1);
  CHECK_NEAR(o1[0], 1 - 2.0, 1e-6);
  CHECK_NEAR(o1[1], 2 + 1.0, 1e-6);
  CHECK_NEAR(o1[2], 3 - 0.25, 1e-6);
  CHECK_NEAR(d1[2], -1, 1e-7);
  CHECK_NEAR(t01, 0.25, 1e-7);
  CHECK(isinf(tm1));
  CHECK_NEAR(pb_camera_pixel_size(&v, 100.0f), 4.0 / 100, 1e-6);
  p[0] = 1.5f, p[1] = 2.5f, p[2] = -7.0f;
  CHECK(pb_camera_view_project(&v, p, &x, &y, &z));
  CHECK_NEAR(x, 50 + 0.5 * 25, 1e-4);
  CHECK_NEAR(y, 25 - 0.5 * 25, 1e-4);
  CHECK_NEAR(z, 10, 1e-5);

  /* The extension: Blender's camera values. 50 mm on a 36 mm sensor,
   * AUTO: fov 2 atan(18 / 50) across the larger side. */
  pb_gltf_camera g = blender_cam("PERSP", NULL);
  g.blender.lens = 50;
  g.blender.shift_x = 0.1;
  pb_camera out;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_OK);
  CHECK_NEAR(out.yfov, 2 * atan(18.0 / 50), 1e-6);
  CHECK_EQ_INT(out.fit, PB_CAMERA_FIT_AUTO);
  CHECK_NEAR(out.shift[0], 0.1, 1e-7);
  CHECK_NEAR(out.znear, 0.1, 1e-7);   /* Blender's defaults */
  CHECK_NEAR(out.zfar, 1000, 1e-3);
  CHECK_NEAR(out.aspect, 1.5, 1e-6);  /* the plain camera's, absent in the extension */
  /* VERTICAL uses the sensor height. */
  g = blender_cam("PERSP", "VERTICAL");
  g.blender.lens = 35, g.blender.sensor_height = 20;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_OK);
  CHECK_NEAR(out.yfov, 2 * atan(10.0 / 35), 1e-6);
  CHECK_EQ_INT(out.fit, PB_CAMERA_FIT_VERTICAL);
  g = blender_cam("ORTHO", "HORIZONTAL");
  g.blender.ortho_scale = 7.5;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_OK);
  CHECK_EQ_INT(out.orthographic, 1);
  CHECK_NEAR(out.ortho_size, 7.5, 1e-6);
  /* Errors name the member; the code says what kind. */
  g = blender_cam("PERSP", NULL);
  g.blender.lens = -1;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 2, &g, &out), PB_ERR_SCENE_INVALID);
  CHECK(strstr(pb_error_message(), "x.gltf: cameras[2].extensions.PHOTONBRIDGE_blender.lens: -1") != NULL);
  pb_error_clear();
  g = blender_cam("PANO", NULL);
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_ERR_SCENE_UNSUPPORTED);
  pb_error_clear();
  g = blender_cam("PERSP", NULL);
  g.blender.bad_member = "shiftX", g.blender.bad_expect = "a number";
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_ERR_SCENE_INVALID);
  CHECK(strstr(pb_error_message(), "PHOTONBRIDGE_blender.shiftX: not a number") != NULL);
  pb_error_clear();
  g = blender_cam("PERSP", NULL);
  g.blender.clip_start = 5, g.blender.clip_end = 4;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_ERR_SCENE_INVALID);
  CHECK(strstr(pb_error_message(), "clipEnd") != NULL);
  pb_error_clear();
  /* The plain camera is still checked (the file must load elsewhere). */
  g = blender_cam("PERSP", NULL);
  g.yfov = 4;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_ERR_SCENE_INVALID);
  pb_error_clear();
  /* Plain orthographic: 2 ymag across the height. */
  pb_gltf_camera po;
  memset(&po, 0, sizeof po);
  po.orthographic = 1, po.xmag = 3, po.ymag = 2, po.znear = 0, po.zfar = 50;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &po, &out), PB_OK);
  CHECK_NEAR(out.ortho_size, 4, 1e-7);
  CHECK_NEAR(out.aspect, 1.5, 1e-7);
  CHECK_EQ_INT(out.fit, PB_CAMERA_FIT_VERTICAL);
  po.ymag = 0;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &po, &out), PB_ERR_SCENE_INVALID);
  pb_error_clear();
  return pbt_done();
}
