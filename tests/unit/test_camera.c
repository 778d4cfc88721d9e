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
                 &g.blender.aspect, &g.blender.focus_distance, &g.blender.aperture_fstop,
                 &g.blender.aperture_blades, &g.blender.aperture_rotation, &g.blender.aperture_ratio,
                 &g.blender.fisheye_fov, &g.blender.fisheye_lens, &g.blender.latitude_min, &g.blender.latitude_max,
                 &g.blender.longitude_min, &g.blender.longitude_max};
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
  g = blender_cam("CUSTOM", NULL);
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_ERR_SCENE_UNSUPPORTED);
  pb_error_clear();
  g = blender_cam("PANO", NULL);
  g.blender.panorama_type = "FISHEYE_LENS_POLYNOMIAL";
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_ERR_SCENE_UNSUPPORTED);
  CHECK(strstr(pb_error_message(), "panoramaType: 'FISHEYE_LENS_POLYNOMIAL'") != NULL);
  pb_error_clear();
  /* Depth of field: Cycles' radius lens / (2 f-stop) (1 / (2 f-stop) when
   * orthographic); absent f-stop: none. */
  g = blender_cam("PERSP", NULL);
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_OK);
  CHECK(out.aperture_radius == 0.0f);
  g.blender.lens = 50, g.blender.aperture_fstop = 2, g.blender.focus_distance = 4, g.blender.aperture_blades = 6;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_OK);
  CHECK_NEAR(out.aperture_radius, 0.0125, 1e-8);
  CHECK_NEAR(out.focus_distance, 4, 1e-7);
  CHECK_EQ_INT((int)out.aperture_blades, 6);
  CHECK_NEAR(out.aperture_ratio, 1, 1e-7);
  g.blender.type = "ORTHO";
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_OK);
  CHECK_NEAR(out.aperture_radius, 0.25, 1e-7);
  g.blender.type = "PERSP", g.blender.aperture_fstop = -1;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 1, &g, &out), PB_ERR_SCENE_INVALID);
  CHECK(strstr(pb_error_message(), "cameras[1].extensions.PHOTONBRIDGE_blender.apertureFstop: -1") != NULL);
  pb_error_clear();
  g.blender.aperture_fstop = 2, g.blender.aperture_blades = 2.5;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 1, &g, &out), PB_ERR_SCENE_INVALID);
  CHECK(strstr(pb_error_message(), "apertureBlades") != NULL);
  pb_error_clear();
  /* Panorama defaults: Blender's fisheye equisolid, 10.5 mm, 180 degrees. */
  g = blender_cam("PANO", NULL);
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_OK);
  CHECK_EQ_INT(out.panorama, PB_CAMERA_PANO_FISHEYE_EQUISOLID);
  CHECK_NEAR(out.fisheye_lens, 10.5, 1e-6);
  CHECK_NEAR(out.fisheye_fov, M_PI, 1e-6);
  g.blender.panorama_type = "EQUIRECTANGULAR", g.blender.latitude_min = -2;
  CHECK_EQ_INT(pb_camera_projection_from_gltf("x.gltf", 0, &g, &out), PB_ERR_SCENE_INVALID);
  CHECK(strstr(pb_error_message(), "latitudeMin: -2") != NULL);
  pb_error_clear();

  /* Thin lens (Cycles' camera_sample_perspective): every lens sample of a
   * pixel meets the pinhole ray at depth `focus`; the lens points lie in
   * the aperture (a disc of the radius; a hexagon inside it). */
  pb_camera d = base();
  d.yfov = 0.8f, d.znear = 0.1f;
  d.aperture_radius = 0.05f, d.focus_distance = 3.0f;
  pb_camera_view(&d, 64, 48, &v);
  float po3[3], pd3[3], pt0, ptm;
  pb_camera_ray(&v, 10.5f, 40.25f, po3, pd3, &pt0, &ptm);
  double pcz = pd3[0] * d.forward[0] + pd3[1] * d.forward[1] + pd3[2] * d.forward[2];
  double far_r = 0, spread = 0;
  for (int blades = 0; blades <= 6; blades += 6) {
    d.aperture_blades = (uint32_t)blades;
    pb_camera_view(&d, 64, 48, &v);
    for (int i = 0; i < 64; ++i) {
      float lens[2] = {(float)((i % 8) + 0.5) / 8.0f, (float)((i / 8) + 0.3) / 8.0f};
      float lo[3], ld[3], lt0, ltm;
      CHECK(pb_camera_ray_lens(&v, 10.5f, 40.25f, lens, lo, ld, &lt0, &ltm));
      double lcz = ld[0] * d.forward[0] + ld[1] * d.forward[1] + ld[2] * d.forward[2];
      /* the ray's origin at the near plane's depth along the pinhole ray's cosine */
      double lens_pt[3], r2 = 0, miss = 0;
      for (int k = 0; k < 3; ++k) lens_pt[k] = lo[k] - ld[k] * lt0 - d.position[k];
      for (int k = 0; k < 3; ++k) r2 += lens_pt[k] * lens_pt[k];
      CHECK(sqrt(r2) <= 0.05 + 1e-6);
      if (sqrt(r2) > far_r) far_r = sqrt(r2);
      /* both rays reach depth 3 at the same point */
      for (int k = 0; k < 3; ++k) {
        double a = lo[k] + ld[k] * (3.0 - (lt0 * lcz)) / lcz;
        double b = po3[k] + pd3[k] * (3.0 - pt0 * pcz) / pcz;
        miss += (a - b) * (a - b);
      }
      CHECK(sqrt(miss) < 1e-5);
      /* and spread at depth 6 */
      double a6 = lo[0] + ld[0] * (6.0 - lt0 * lcz) / lcz, b6 = po3[0] + pd3[0] * (6.0 - pt0 * pcz) / pcz;
      if (fabs(a6 - b6) > spread) spread = fabs(a6 - b6);
    }
  }
  CHECK(far_r > 0.04);
  CHECK(spread > 0.03 && spread <= 0.05 + 1e-4); /* circle of confusion: R |6 - 3| / 3 */

  /* Cycles' regular_polygon_sample: 5 blades turned by 0.3 rad fill the
   * pentagon with corners at 0.3 + (2k + 1) pi / 5 (apothem cos(pi / 5)
   * toward 0.3 + 2k pi / 5), reaching near every corner; ratio 2 halves x. */
  d.aperture_radius = 1.0f, d.aperture_blades = 5, d.aperture_rotation = 0.3f, d.aperture_ratio = 1.0f;
  d.znear = 0.0f;
  for (int pass = 0; pass < 2; ++pass) {
    pb_camera_view(&d, 64, 48, &v);
    double outside = 0, corner_near[5] = {9, 9, 9, 9, 9}, max_x = 0;
    for (int i = 0; i < 4096; ++i) {
      float lens[2] = {(float)((i % 64) + 0.5) / 64.0f, (float)((i / 64) + 0.5) / 64.0f};
      float lo[3], ld[3], lt0, ltm;
      pb_camera_ray_lens(&v, 32, 24, lens, lo, ld, &lt0, &ltm);
      double ax = (lo[0] - d.position[0]) * (pass ? 2.0 : 1.0), ay = lo[1] - d.position[1];
      if (fabs(ax) > max_x) max_x = fabs(ax);
      for (int k = 0; k < 5; ++k) {
        double a = 0.3 + 2 * k * M_PI / 5, b = 0.3 + (2 * k + 1) * M_PI / 5;
        double proj = ax * cos(a) + ay * sin(a) - cos(M_PI / 5);
        if (proj > outside) outside = proj;
        double dc = hypot(ax - cos(b), ay - sin(b));
        if (dc < corner_near[k]) corner_near[k] = dc;
      }
    }
    CHECK(outside < 1e-5);
    for (int k = 0; k < 5; ++k) CHECK(corner_near[k] < 0.1);
    if (pass == 0) {
      CHECK(max_x > 0.9);
      d.aperture_ratio = 2.0f;
    }
  }

  /* Equirectangular (Cycles' defaults: all longitudes, all latitudes):
   * the centre looks along forward, three quarters across to the right,
   * the top row up; projection inverts the ray. */
  pb_camera e = base();
  e.yfov = 0.8f, e.znear = 0.1f, e.zfar = 100.0f;
  e.panorama = PB_CAMERA_PANO_EQUIRECTANGULAR;
  e.latitude[0] = (float)(-M_PI / 2), e.latitude[1] = (float)(M_PI / 2);
  e.longitude[0] = (float)-M_PI, e.longitude[1] = (float)M_PI;
  pb_camera_view(&e, 80, 40, &v);
  CHECK_EQ_INT((int)v.projection, PB_GPU_CAMERA_EQUIRECTANGULAR);
  pb_camera_ray(&v, 40, 20, o1, d1, &t01, &tm1);
  CHECK_NEAR(d1[2], -1, 1e-5);
  CHECK_NEAR(t01, 0.1, 1e-7);
  CHECK_NEAR(tm1, 99.9, 1e-3);
  pb_camera_ray(&v, 60, 20, o1, d1, &t01, &tm1);
  CHECK_NEAR(d1[0], 1, 1e-5);
  pb_camera_ray(&v, 40, 0, o1, d1, &t01, &tm1);
  CHECK_NEAR(d1[1], 1, 1e-5);
  pb_camera_ray(&v, 13.25f, 31.5f, o1, d1, &t01, &tm1);
  for (int k = 0; k < 3; ++k) p[k] = o1[k] + 2.0f * d1[k];
  CHECK(pb_camera_view_project(&v, p, &x, &y, &z));
  CHECK_NEAR(x, 13.25, 1e-3);
  CHECK_NEAR(y, 31.5, 1e-3);
  CHECK_NEAR(z, 2.1, 1e-4);
  CHECK_NEAR(pb_camera_pixel_size(&v, 1.0f), M_PI / 40, 1e-6);
  /* A panorama's thin lens (camera_sample_panorama): every lens ray of a
   * pixel passes through the pinhole ray's point at distance focus, from a
   * lens point normal to it within the radius; the centre pixel's pinhole
   * ray is the frame's x itself (Cycles' U degenerates there). */
  e.aperture_radius = 0.1f, e.focus_distance = 2.5f;
  pb_camera_view(&e, 80, 40, &v);
  for (int pix = 0; pix < 2; ++pix) {
    float qx = pix ? 40.0f : 13.25f, qy = pix ? 20.0f : 31.5f;
    pb_camera_ray(&v, qx, qy, o1, d1, &t01, &tm1);
    double focus_pt[3], worst_miss = 0, worst_r = 0, worst_dot = 0;
    for (int k = 0; k < 3; ++k) focus_pt[k] = e.position[k] + 2.5 * d1[k];
    for (int i = 0; i < 16; ++i) {
      float lens[2] = {(float)((i % 4) + 0.5) / 4.0f, (float)((i / 4) + 0.5) / 4.0f}, lo[3], ld[3], lt0, ltm;
      CHECK(pb_camera_ray_lens(&v, qx, qy, lens, lo, ld, &lt0, &ltm));
      double a[3], w[3], along = 0, miss = 0, r2 = 0, dn = 0;
      for (int k = 0; k < 3; ++k) a[k] = lo[k] - ld[k] * lt0; /* the lens point */
      for (int k = 0; k < 3; ++k) w[k] = focus_pt[k] - a[k], along += w[k] * ld[k];
      for (int k = 0; k < 3; ++k) miss += (w[k] - along * ld[k]) * (w[k] - along * ld[k]);
      for (int k = 0; k < 3; ++k) r2 += (a[k] - e.position[k]) * (a[k] - e.position[k]);
      for (int k = 0; k < 3; ++k) dn += (a[k] - e.position[k]) * d1[k];
      worst_miss = fmax(worst_miss, sqrt(miss));
      worst_r = fmax(worst_r, sqrt(r2));
      worst_dot = fmax(worst_dot, fabs(dn));
    }
    CHECK(worst_miss < 1e-5);
    CHECK(worst_r <= 0.1 + 1e-6 && worst_r > 0.05);
    CHECK(worst_dot < 1e-6);
  }
  e.aperture_radius = 0.0f;
  /* Fisheyes: the corners are outside the circle (no ray); the centre
   * looks along forward; projection inverts the ray. */
  for (int kind = PB_CAMERA_PANO_FISHEYE_EQUIDISTANT; kind <= PB_CAMERA_PANO_MIRRORBALL; ++kind) {
    e.panorama = kind;
    e.fisheye_fov = (float)M_PI, e.fisheye_lens = 10.5f, e.sensor[0] = 36, e.sensor[1] = 24;
    e.fit = PB_CAMERA_FIT_AUTO;
    pb_camera_view(&e, 60, 60, &v);
    CHECK(!pb_camera_ray_lens(&v, 0.5f, 0.5f, NULL, o1, d1, &t01, &tm1));
    CHECK(tm1 == 0.0f);
    CHECK(pb_camera_ray_lens(&v, 30, 30, NULL, o1, d1, &t01, &tm1));
    CHECK_NEAR(d1[2], -1, 1e-5);
    CHECK(pb_camera_ray_lens(&v, 40.5f, 21.0f, NULL, o1, d1, &t01, &tm1));
    CHECK(d1[0] > 0.1 && d1[1] > 0.1); /* right of and above the centre */
    for (int k = 0; k < 3; ++k) p[k] = o1[k] + 2.0f * d1[k];
    CHECK(pb_camera_view_project(&v, p, &x, &y, &z));
    CHECK_NEAR(x, 40.5, 2e-3);
    CHECK_NEAR(y, 21.0, 2e-3);
  }
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
