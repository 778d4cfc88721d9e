/* What Blender's glTF exporter writes beyond the core, rendered by the GPU
 * pipeline and the reference renderer (scenes: tests/data/gltf_ext, written
 * by its make_scenes.py, which says what each holds). Every scene looks
 * straight down at y = 0, so a pixel's point on the floor is known exactly
 * (the camera ray of motion.h's pb_camera_primary_rays), and the sun of
 * E = pi W/m^2 makes a Lambertian albedo rho show radiance rho:
 *   - COLOR_0 (float, normalized UBYTE, normalized USHORT) times the base
 *     colour: every pixel inside a triangle against the barycentric
 *     interpolation of the corner colours (GPU at pixel centres within 2e-4,
 *     reference within the range of the pixel's corners, as its samples
 *     spread over the pixel);
 *   - KHR_texture_transform with its texCoord (TEXCOORD_1) on the base colour
 *     and emissive slots against the same texture baked through the
 *     transform: 99 % of the pixels equal within 1e-4, in both renderers;
 *   - KHR_materials_unlit: its colour exactly, lit or not; a floor under it
 *     and no light stays exactly black (it lights nothing);
 *   - a spot of blend 0 (innerConeAngle = outerConeAngle): hard-edged, every
 *     pixel wholly inside at rho/pi I cos/d^2 (GPU: 1e-4 at the centre,
 *     reference: within the pixel's range), every one wholly outside exactly
 *     0;
 *   - a primitive without material in a Blender file: Cycles' default
 *     surface, albedo 0.8;
 *   - KHR_materials_volume: the radiance through a slab (0.2 m, attenuation
 *     colour 0.5 at 0.2 m) over the clear slab's is exp(-sigma d) x the
 *     internal reflections' (1 - F^2) / (1 - F^2 exp(-2 sigma d)) = 0.4994
 *     on the eye path, and the caustic photons' irradiance under it, seen
 *     through it, that squared within 5 % (GPU photon tracer, reference
 *     SPPM).
 * Validation layers on; exit 77 without a device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "ref/ref.h"
#include "render/scene/motion.h"
#include "render/render.h"

static int load(const char *name, pb_scene *s) {
  char path[256];
  snprintf(path, sizeof path, "tests/data/gltf_ext/%s.gltf", name);
  pb_result r = pb_scene_load(path, NULL, s);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  CHECK_EQ_INT(r, PB_OK);
  return r == PB_OK;
}

/* GPU frame (direct_only or the full pipeline) and a reference render. */
static int render_gpu(pb_gpu *g, const pb_scene *s, uint32_t w, uint32_t h, const pb_render_desc *rd,
                      pb_render_result *out) {
  pb_gpu_scene gs;
  memset(out, 0, sizeof *out);
  pb_result r = pb_gpu_scene_create(g, s, &gs);
  if (r == PB_OK) r = pb_render_frame(g, s, &gs, 0, w, h, rd, out);
  pb_gpu_scene_destroy(g, &gs);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  CHECK_EQ_INT(r, PB_OK);
  return r == PB_OK;
}

static int render_ref(const pb_scene *s, uint32_t w, uint32_t h, const pb_ref_desc *d, pb_ref_result *out) {
  memset(out, 0, sizeof *out);
  pb_result r = pb_ref_render(s, 0, w, h, d, out);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  CHECK_EQ_INT(r, PB_OK);
  return r == PB_OK;
}

/* Where the camera ray through image point (fx, fy) meets y = 0. */
static void floor_point(const pb_camera *c, uint32_t w, uint32_t h, double fx, double fy, double p[3]) {
  double ty = tan(0.5 * c->yfov), tx = ty * w / h;
  double sx = (2 * fx / w - 1) * tx, sy = (1 - 2 * fy / h) * ty, d[3];
  for (int k = 0; k < 3; ++k) d[k] = c->forward[k] + c->right[k] * sx + c->up[k] * sy;
  double t = -c->position[1] / d[1];
  for (int k = 0; k < 3; ++k) p[k] = c->position[k] + t * d[k];
}

/* ---- COLOR_0 ---------------------------------------------------------------- */

/* The analytic colour at floor point p: which quad (x in [-3,-1], [-1,1],
 * [1,3]) and which triangle of it (corners (x0,z0) (x0,z1) (x1,z1) (x1,z0),
 * triangles 0 1 2 and 0 2 3), -1 outside; rgb = base x barycentric mix. */
static int vc_colour(const double p[3], double rgb[3]) {
  static const double corner[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}}, base[3] = {0.5, 1, 0.8};
  if (p[0] < -3 || p[0] > 3 || p[2] < -1 || p[2] > 1) return -1;
  double x0 = p[0] < -1 ? -3 : p[0] < 1 ? -1 : 1;
  double u = (p[0] - x0) / 2, v = (p[2] + 1) / 2; /* corner 0 (0,0), 1 (0,1), 2 (1,1), 3 (1,0) */
  double w[4] = {0, 0, 0, 0};
  int tri;
  if (v >= u) tri = 0, w[0] = 1 - v, w[1] = v - u, w[2] = u; /* triangle 0 1 2 */
  else tri = 1, w[0] = 1 - u, w[2] = v, w[3] = u - v;        /* triangle 0 2 3 */
  for (int k = 0; k < 3; ++k) {
    rgb[k] = 0;
    for (int c = 0; c < 4; ++c) rgb[k] += w[c] * corner[c][k];
    rgb[k] *= base[k];
  }
  return (int)((x0 + 3) / 2) * 2 + tri;
}

static void vertex_colors(pb_gpu *g) {
  pb_scene s;
  if (!load("vertex_colors", &s)) return;
  CHECK(s.colors != NULL);
  CHECK(s.features & PB_FEATURE_VERTEX_COLORS);
  const uint32_t W = 96, H = 32;
  pb_render_desc rd = {.direct_only = 1};
  pb_ref_desc fd = {.spp = 16, .max_bounces = 1, .seed = 5, .mode = PB_REF_MODE_PT, .threads = 2};
  pb_render_result gr;
  pb_ref_result rr;
  int ok = render_gpu(g, &s, W, H, &rd, &gr);
  ok &= render_ref(&s, W, H, &fd, &rr);
  if (ok) {
    double err_gpu = 0, err_ref = 0, span = 0;
    uint32_t inside = 0;
    const pb_camera *c = &s.cameras[0];
    for (uint32_t y = 0; y < H; ++y)
      for (uint32_t x = 0; x < W; ++x) {
        double p[3], want[3], q[3], lo[3], hi[3];
        floor_point(c, W, H, x + 0.5, y + 0.5, p);
        int tri = vc_colour(p, want);
        int same = tri >= 0;
        for (int k = 0; k < 3; ++k) lo[k] = hi[k] = want[k];
        for (int k = 0; k < 4 && same; ++k) { /* the whole pixel in one triangle */
          floor_point(c, W, H, x + (k & 1), y + (k >> 1), q);
          double t[3];
          same = vc_colour(q, t) == tri;
          for (int j = 0; j < 3; ++j) lo[j] = fmin(lo[j], t[j]), hi[j] = fmax(hi[j], t[j]);
        }
        if (!same) continue;
        inside++;
        size_t i = (size_t)y * W + x;
        for (int k = 0; k < 3; ++k) {
          err_gpu = fmax(err_gpu, fabs(gr.direct[3 * i + k] - want[k]));
          /* The reference's samples spread over the pixel: its mean lies
           * within the colours of the pixel's corners (affine in it). */
          double v = rr.direct[3 * i + k];
          err_ref = fmax(err_ref, v < lo[k] ? lo[k] - v : v > hi[k] ? v - hi[k] : 0);
          span = fmax(span, want[k]);
        }
      }
    printf("COLOR_0 (float, UBYTE, USHORT) x base colour, %ux%u: %u pixels inside a triangle, max |error| GPU %.2g "
           "(pixel centres), reference %.2g (outside the pixel's corner colours; colours up to %.2f)\n",
           W, H, inside, err_gpu, err_ref, span);
    CHECK(inside > W * H / 2);
    CHECK(err_gpu < 2e-4);
    CHECK(err_ref < 2e-4);
  }
  pb_render_result_destroy(&gr);
  pb_ref_result_destroy(&rr);
  pb_scene_destroy(&s);
}

/* ---- KHR_texture_transform --------------------------------------------------- */

static double equal_fraction(const float *a, const float *b, size_t n, double tol, double *range) {
  size_t same = 0;
  double lo = INFINITY, hi = -INFINITY;
  for (size_t i = 0; i < n; ++i) {
    int e = 1;
    for (int k = 0; k < 3; ++k) {
      e &= fabs(a[3 * i + k] - b[3 * i + k]) <= tol;
      lo = fmin(lo, a[3 * i + k]), hi = fmax(hi, a[3 * i + k]);
    }
    same += (size_t)e;
  }
  *range = hi - lo;
  return (double)same / (double)n;
}

static void texture_transform(pb_gpu *g) {
  pb_scene a, b;
  if (!load("texture_transform", &a)) return;
  if (!load("texture_baked", &b)) {
    pb_scene_destroy(&a);
    return;
  }
  CHECK(a.uvs1 != NULL);
  CHECK_EQ_INT(a.texture_count, 1);
  if (a.texture_count == 1) {
    CHECK_EQ_INT(a.textures[0].texcoord, 1);
    CHECK(a.textures[0].uv_transformed);
    CHECK_NEAR(a.textures[0].uv_xform[1], 0.5, 1e-6);  /* u' = 0.5 v */
    CHECK_NEAR(a.textures[0].uv_xform[3], -0.5, 1e-6); /* v' = 1 - 0.5 u */
    CHECK_NEAR(a.textures[0].uv_xform[5], 1, 1e-6);
  }
  CHECK(a.materials[0].emissive_tex == a.materials[0].base_color_tex);
  const uint32_t W = 32, H = 32;
  pb_render_desc rd = {.direct_only = 1};
  pb_ref_desc fd = {.spp = 4, .max_bounces = 1, .seed = 9, .mode = PB_REF_MODE_PT, .threads = 2};
  pb_render_result ga, gb;
  pb_ref_result ra, rb;
  int ok = render_gpu(g, &a, W, H, &rd, &ga) & render_gpu(g, &b, W, H, &rd, &gb);
  ok &= render_ref(&a, W, H, &fd, &ra) & render_ref(&b, W, H, &fd, &rb);
  if (ok) {
    double range_g, range_r;
    double fg = equal_fraction(ga.direct, gb.direct, (size_t)W * H, 1e-4, &range_g);
    double fr = equal_fraction(ra.direct, rb.direct, (size_t)W * H, 1e-4, &range_r);
    printf("KHR_texture_transform (rotation, scale, offset, texCoord 1; base colour and emissive) vs the texture baked "
           "through it, %ux%u: pixels equal within 1e-4: GPU %.1f %%, reference %.1f %% (image range %.2f)\n",
           W, H, 100 * fg, 100 * fr, range_g);
    CHECK(fg >= 0.99);
    CHECK(fr >= 0.99);
    CHECK(range_g > 0.3); /* the texture shows, not one texel */
  }
  pb_render_result_destroy(&ga);
  pb_render_result_destroy(&gb);
  pb_ref_result_destroy(&ra);
  pb_ref_result_destroy(&rb);
  pb_scene_destroy(&a);
  pb_scene_destroy(&b);
}

/* ---- KHR_materials_unlit ---------------------------------------------------- */

static void unlit(pb_gpu *g) {
  static const double colour[3] = {0.2, 0.5, 0.8};
  for (int lit = 0; lit < 2; ++lit) {
    pb_scene s;
    if (!load(lit ? "unlit_lit" : "unlit_dark", &s)) return;
    CHECK(s.features & PB_FEATURE_UNLIT);
    const uint32_t W = 32, H = 32;
    pb_render_desc rd = {.spp = 4, .photons = 1 << 14, .seed = 2};
    pb_ref_desc fd = {.spp = 16, .seed = 4, .mode = PB_REF_MODE_PT, .threads = 2};
    pb_render_result gr;
    pb_ref_result rr;
    int ok = render_gpu(g, &s, W, H, &rd, &gr);
    ok &= render_ref(&s, W, H, &fd, &rr);
    if (ok) {
      double card_g = 0, card_r = 0, floor_g = 0, floor_r = 0;
      uint32_t nc = 0, nf = 0;
      const pb_camera *c = &s.cameras[0];
      for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
          /* The card is at y = 0.5: its pixels from the camera 3.5 above it. */
          int card = 1, floor = 1;
          for (int k = 0; k < 4; ++k) {
            double p[3];
            floor_point(c, W, H, x + (k & 1), y + (k >> 1), p);
            double sc = 3.5 / 4.0; /* the card's plane scales the footprint */
            card &= fabs(p[0] * sc) < 0.5 && fabs(p[2] * sc) < 0.5;
            floor &= fabs(p[0]) < 2 && fabs(p[2]) < 2 && !(fabs(p[0] * sc) < 0.55 && fabs(p[2] * sc) < 0.55);
          }
          size_t i = (size_t)y * W + x;
          for (int k = 0; k < 3; ++k) {
            if (card) {
              card_g = fmax(card_g, fabs(gr.beauty[4 * i + k] - colour[k]));
              card_r = fmax(card_r, fabs(rr.beauty[4 * i + k] - colour[k]));
            } else if (floor && !lit) {
              floor_g = fmax(floor_g, fabs(gr.beauty[4 * i + k]));
              floor_r = fmax(floor_r, fabs(rr.beauty[4 * i + k]));
            }
          }
          nc += (uint32_t)card, nf += (uint32_t)floor;
        }
      printf("unlit card (0.2 0.5 0.8), %s, %ux%u, full GI: %u card pixels, max |error| GPU %.2g, reference %.2g",
             lit ? "under the sun" : "no light", W, H, nc, card_g, card_r);
      if (!lit) printf("; floor (%u pixels) max GPU %.2g, reference %.2g (must be 0)", nf, floor_g, floor_r);
      printf("\n");
      CHECK(nc > 16 && nf > 16);
      CHECK(card_g < 1e-5 && card_r < 1e-5);
      CHECK(floor_g == 0 && floor_r == 0);
    }
    pb_render_result_destroy(&gr);
    pb_ref_result_destroy(&rr);
    pb_scene_destroy(&s);
  }
}

/* ---- blend-0 spot ------------------------------------------------------------ */

static void spot_blend0(pb_gpu *g) {
  pb_scene s;
  if (!load("spot_blend0", &s)) return;
  CHECK(s.light_count == 1 && s.lights[0].inner_cone == s.lights[0].outer_cone);
  const uint32_t W = 48, H = 48;
  pb_render_desc rd = {.direct_only = 1};
  pb_ref_desc fd = {.spp = 16, .max_bounces = 1, .seed = 6, .mode = PB_REF_MODE_PT, .threads = 2};
  pb_render_result gr;
  pb_ref_result rr;
  int ok = render_gpu(g, &s, W, H, &rd, &gr);
  ok &= render_ref(&s, W, H, &fd, &rr);
  if (ok) {
    const pb_light *l = &s.lights[0];
    double co = cos(l->outer_cone), eg = 0, er = 0, og = 0, orf = 0;
    uint32_t ni = 0, no = 0;
    for (uint32_t y = 0; y < H; ++y)
      for (uint32_t x = 0; x < W; ++x) {
        /* rho/pi I cos / d^2 with cos = 2/d at the floor: 2 rho I / (pi d^3),
         * monotonic in d, so a pixel's mean lies within its corners' values
         * unless it holds the point under the light (its centre's counts). */
        int in = 1, out = 1;
        double lo = INFINITY, hi = 0;
        for (int k = 0; k < 5; ++k) {
          double p[3];
          floor_point(&s.cameras[0], W, H, k < 4 ? x + (k & 1) : x + 0.5, k < 4 ? y + (k >> 1) : y + 0.5, p);
          double d = sqrt(p[0] * p[0] + 4 + p[2] * p[2]), c = 2 / d, v = 0.8 / M_PI * l->intensity * c / (d * d);
          in &= c > co, out &= c < co;
          lo = fmin(lo, v), hi = fmax(hi, v);
        }
        double p[3];
        floor_point(&s.cameras[0], W, H, x + 0.5, y + 0.5, p);
        double d2 = p[0] * p[0] + 4 + p[2] * p[2], c = 2 / sqrt(d2);
        double want = 0.8 / M_PI * l->intensity * c / d2;
        size_t i = (size_t)y * W + x;
        if (in) {
          ni++;
          eg = fmax(eg, fabs(gr.direct[3 * i + 1] - want) / want);
          double v = rr.direct[3 * i + 1];
          er = fmax(er, (v < lo ? lo - v : v > hi ? v - hi : 0) / want);
        } else if (out) {
          no++;
          og = fmax(og, gr.direct[3 * i + 1]), orf = fmax(orf, rr.direct[3 * i + 1]);
        }
      }
    printf("spot, innerConeAngle = outerConeAngle: %u pixels wholly inside (max relative error GPU %.2g at the centre, "
           "reference %.2g outside the pixel's range), "
           "%u wholly outside (max GPU %g, reference %g)\n",
           ni, eg, er, no, og, orf);
    CHECK(ni > 100 && no > 100);
    CHECK(eg < 1e-4 && er < 1e-4);
    CHECK(og == 0 && orf == 0);
  }
  pb_render_result_destroy(&gr);
  pb_ref_result_destroy(&rr);
  pb_scene_destroy(&s);
}

/* ---- default material --------------------------------------------------------- */

static void default_material(pb_gpu *g) {
  pb_scene b, o;
  if (!load("default_blender", &b)) return;
  if (!load("default_gltf", &o)) {
    pb_scene_destroy(&b);
    return;
  }
  CHECK_EQ_INT(b.material_count, 1);
  CHECK_EQ_INT(o.material_count, 1);
  if (b.material_count == 1 && o.material_count == 1) {
    CHECK(strcmp(b.materials[0].name, "(Blender default surface)") == 0);
    CHECK_NEAR(b.materials[0].base_color[0], 0.8, 1e-6);
    CHECK_NEAR(b.materials[0].metallic, 0, 0);
    CHECK_NEAR(b.materials[0].specular, 0, 0);
    CHECK_EQ_INT(pb_material_kind(&b.materials[0]), PB_BSDF_DIFFUSE);
    CHECK(strcmp(o.materials[0].name, "(glTF default)") == 0);
    CHECK_NEAR(o.materials[0].metallic, 1, 0);
    CHECK_NEAR(o.materials[0].base_color[0], 1, 0);
  }
  const uint32_t W = 8, H = 8;
  pb_render_desc rd = {.direct_only = 1};
  pb_ref_desc fd = {.spp = 8, .max_bounces = 1, .seed = 1, .mode = PB_REF_MODE_PT, .threads = 2};
  pb_render_result gr;
  pb_ref_result rr;
  if (render_gpu(g, &b, W, H, &rd, &gr) & render_ref(&b, W, H, &fd, &rr)) {
    size_t c = (size_t)(H / 2) * W + W / 2;
    printf("no material in a Blender file: centre GPU %.6f, reference %.6f (Cycles' default surface: 0.8)\n",
           gr.direct[3 * c], rr.direct[3 * c]);
    CHECK_NEAR(gr.direct[3 * c], 0.8, 1e-4);
    CHECK_NEAR(rr.direct[3 * c], 0.8, 1e-4);
  }
  pb_render_result_destroy(&gr);
  pb_ref_result_destroy(&rr);
  pb_scene_destroy(&b);
  pb_scene_destroy(&o);
}

/* ---- KHR_materials_volume ------------------------------------------------------ */

/* Mean of channel 1 of `img` (stride floats per pixel) over the central
 * n x n pixels. */
static double centre_mean(const float *img, uint32_t w, uint32_t h, int stride, uint32_t n) {
  double s = 0;
  for (uint32_t y = h / 2 - n / 2; y < h / 2 + n / 2; ++y)
    for (uint32_t x = w / 2 - n / 2; x < w / 2 + n / 2; ++x) s += img[((size_t)y * w + x) * (size_t)stride + 1];
  return s / (n * n);
}

static void volume(pb_gpu *g) {
  /* Eye paths: the unlit white floor seen through the slab. */
  const double F = 0.04, T = 0.5; /* Fresnel at normal incidence for ior 1.5; exp(-sigma d) */
  const double want = T * (1 - F * F) / (1 - F * F * T * T);
  pb_scene a, c;
  if (!load("volume_eye", &a)) return;
  if (!load("volume_eye_clear", &c)) {
    pb_scene_destroy(&a);
    return;
  }
  CHECK(a.features & PB_FEATURE_VOLUME);
  CHECK_NEAR(a.materials[0].attenuation[1], log(2.0) / 0.2, 1e-4);
  const uint32_t W = 16, H = 16;
  pb_render_desc rd = {.spp = 256, .seed = 3};
  pb_ref_desc fd = {.spp = 256, .seed = 7, .mode = PB_REF_MODE_PT, .threads = 2};
  pb_render_result ga, gc;
  pb_ref_result ra, rc;
  int ok = render_gpu(g, &a, W, H, &rd, &ga) & render_gpu(g, &c, W, H, &rd, &gc);
  ok &= render_ref(&a, W, H, &fd, &ra) & render_ref(&c, W, H, &fd, &rc);
  if (ok) {
    double qg = centre_mean(ga.beauty, W, H, 4, 4) / centre_mean(gc.beauty, W, H, 4, 4);
    double qr = centre_mean(ra.beauty, W, H, 4, 4) / centre_mean(rc.beauty, W, H, 4, 4);
    printf("KHR_materials_volume, eye paths through 0.2 m (attenuation 0.5 at 0.2 m), %ux%u, 256 spp: through the "
           "absorbing slab / the clear one: GPU %.4f, reference %.4f, expected %.4f\n",
           W, H, qg, qr, want);
    CHECK_NEAR(qg, want, 0.01 * want);
    CHECK_NEAR(qr, want, 0.01 * want);
  }
  pb_render_result_destroy(&ga);
  pb_render_result_destroy(&gc);
  pb_ref_result_destroy(&ra);
  pb_ref_result_destroy(&rc);
  pb_scene_destroy(&a);
  pb_scene_destroy(&c);

  /* Photon paths: the floor under the slab is lit through it only. */
  if (!load("volume_photons", &a)) return;
  if (!load("volume_photons_clear", &c)) {
    pb_scene_destroy(&a);
    return;
  }
  pb_render_desc pd = {.spp = 4, .photons = 1 << 17, .iterations = 2, .seed = 8};
  pb_ref_desc sd = {.spp = 16, .seed = 9, .mode = PB_REF_MODE_SPPM, .threads = 2, .photons_per_pass = 1 << 15};
  ok = render_gpu(g, &a, W, H, &pd, &ga) & render_gpu(g, &c, W, H, &pd, &gc);
  ok &= render_ref(&a, W, H, &sd, &ra) & render_ref(&c, W, H, &sd, &rc);
  if (ok && ga.caustic && gc.caustic) {
    /* Light crosses the slab on its way to the floor, and the camera sees
     * the floor through it: the attenuation twice. */
    double qg = centre_mean(ga.caustic, W, H, 3, 6) / centre_mean(gc.caustic, W, H, 3, 6);
    double qr = centre_mean(ra.beauty, W, H, 4, 6) / centre_mean(rc.beauty, W, H, 4, 6);
    printf("KHR_materials_volume, caustic photons through the slab onto the floor seen through it: absorbing / clear: "
           "GPU %.4f, reference (SPPM) %.4f, expected %.4f\n",
           qg, qr, want * want);
    CHECK_NEAR(qg, want * want, 0.05 * want * want);
    CHECK_NEAR(qr, want * want, 0.05 * want * want);
  } else {
    CHECK(ok && ga.caustic && gc.caustic);
  }
  pb_render_result_destroy(&ga);
  pb_render_result_destroy(&gc);
  pb_ref_result_destroy(&ra);
  pb_ref_result_destroy(&rc);
  pb_scene_destroy(&a);
  pb_scene_destroy(&c);
}

int main(void) {
  PBT_GPU_OPEN(g);
  vertex_colors(g);
  texture_transform(g);
  unlit(g);
  spot_blend0(g);
  default_material(g);
  volume(g);
  pb_gpu_destroy(g);
  return pbt_done();
}
