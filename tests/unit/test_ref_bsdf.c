/* The reference's material model and ray offsets in isolation:
 *  - importance sampling is consistent with evaluation: the mean sample
 *    weight E[f cos / pdf] equals the albedo integral of f cos over the
 *    hemisphere estimated independently with uniform directions (within
 *    1.5 %), and each sample's pdf equals pb_bsdf_eval's pdf for its
 *    direction (1e-4 relative);
 *  - the Lambertian lobe has albedo rho exactly; the metal GGX lobe is
 *    reciprocal, f(wo, wi) = f(wi, wo);
 *  - a smooth dielectric at normal incidence reflects ((n-1)/(n+1))^2 of
 *    the samples, and its refraction obeys Snell's law;
 *  - Waechter & Binder offsets leave the surface on the requested side for
 *    points near and far from the origin. */
#include "pbtest.h"
#include "ref/bsdf.h"
#include "ref/lights.h"
#include "test_ref_scene.h"

static pb_scene scene; /* textures only; materials set per case */

static void setup(pb_material *m, v3 wo, pb_bsdf *b) {
  pb_surface surf;
  memset(&surf, 0, sizeof surf);
  surf.ng = surf.ns = v3_make(0, 0, 1);
  surf.front = 1;
  surf.mat = m;
  surf.color[0] = surf.color[1] = surf.color[2] = surf.color[3] = 1; /* no COLOR_0 */
  pb_bsdf_setup(&scene, &surf, wo, NULL, b);
}

static v3 dir_from_theta(float theta_deg) {
  float t = theta_deg * PB_PI_F / 180.0f;
  return v3_make(sinf(t), 0.0f, cosf(t));
}

static void consistency(const char *what, pb_material m, float theta) {
  v3 wo = dir_from_theta(theta);
  pb_bsdf b;
  setup(&m, wo, &b);
  pb_rng rng = pb_rng_make(1, 9, 2, 3);
  enum { N = 400000 };
  /* Uniform hemisphere estimate of int f cos. */
  double uni[3] = {0, 0, 0};
  for (int i = 0; i < N; ++i) {
    float u1 = pb_rng_f(&rng), u2 = pb_rng_f(&rng);
    float z = u1, r = sqrtf(fmaxf(0.0f, 1.0f - z * z)), phi = 2.0f * PB_PI_F * u2;
    v3 wi = v3_make(r * cosf(phi), r * sinf(phi), z);
    float pdf;
    v3 f = pb_bsdf_eval(&b, wo, wi, &pdf);
    for (int c = 0; c < 3; ++c) uni[c] += v3_get(f, c) * z * 2.0 * M_PI / N;
  }
  double imp[3] = {0, 0, 0};
  int pdf_bad = 0;
  for (int i = 0; i < N; ++i) {
    pb_bsdf_sample s;
    if (!pb_bsdf_sample_dir(&b, wo, pb_rng_f(&rng), pb_rng_f(&rng), pb_rng_f(&rng),
                            PB_RADIANCE, &s))
      continue;
    if (s.delta) continue; /* only smooth lobes here */
    float pdf;
    pb_bsdf_eval(&b, wo, s.wi, &pdf);
    if (fabsf(pdf - s.pdf) > 1e-4f * pdf) pdf_bad++;
    for (int c = 0; c < 3; ++c) imp[c] += v3_get(s.weight, c) / N;
  }
  printf("%-22s theta %4.0f: uniform %.4f %.4f %.4f  importance %.4f %.4f %.4f\n", what,
         (double)theta, uni[0], uni[1], uni[2], imp[0], imp[1], imp[2]);
  CHECK_EQ_INT(pdf_bad, 0);
  for (int c = 0; c < 3; ++c) CHECK_NEAR(imp[c], uni[c], 0.015 * uni[c] + 1e-4);
}

static void test_lambert(void) {
  pb_material m = tsc_lambert(0.9f, 0.5f, 0.1f);
  v3 wo = dir_from_theta(30);
  pb_bsdf b;
  setup(&m, wo, &b);
  float pdf;
  v3 f = pb_bsdf_eval(&b, wo, dir_from_theta(-60), &pdf);
  CHECK_NEAR(f.x, 0.9 / M_PI, 1e-6);
  CHECK_NEAR(f.z, 0.1 / M_PI, 1e-6);
  CHECK_NEAR(pdf, cos(60 * M_PI / 180) / M_PI, 1e-6);
  /* Below the surface: nothing. */
  f = pb_bsdf_eval(&b, wo, v3_make(0, 0, -1), &pdf);
  CHECK(v3_is_zero(f) && pdf == 0.0f);
  consistency("lambert", m, 30);
}

static void test_ggx(void) {
  pb_material metal = tsc_lambert(0.95f, 0.64f, 0.54f);
  metal.metallic = 1;
  metal.roughness = 0.3f;
  consistency("metal r=0.3", metal, 0);
  /* (A narrower lobe at grazing angles needs far more uniform samples than
   * a unit test can afford for the comparison to be meaningful.) */
  metal.roughness = 0.5f;
  consistency("metal r=0.5", metal, 70);
  metal.roughness = 0.8f;
  consistency("metal r=0.8", metal, 45);
  pb_material plastic = tsc_lambert(0.2f, 0.4f, 0.8f);
  plastic.roughness = 0.4f;
  plastic.specular = 1;
  plastic.specular_color[0] = plastic.specular_color[1] = plastic.specular_color[2] = 1;
  consistency("dielectric r=0.4", plastic, 20);
  consistency("dielectric r=0.4", plastic, 80);
  plastic.metallic = 0.5f;
  consistency("half metal r=0.4", plastic, 50);

  /* Reciprocity of the (single-lobe) metal BRDF. */
  metal.roughness = 0.5f;
  v3 a = v3_norm(v3_make(0.3f, -0.2f, 0.9f)), c = v3_norm(v3_make(-0.6f, 0.1f, 0.5f));
  pb_bsdf b1, b2;
  setup(&metal, a, &b1);
  setup(&metal, c, &b2);
  float p;
  v3 f1 = pb_bsdf_eval(&b1, a, c, &p), f2 = pb_bsdf_eval(&b2, c, a, &p);
  CHECK_NEAR(f1.x, f2.x, 1e-5 * f1.x);
  CHECK_NEAR(f1.y, f2.y, 1e-5 * f1.y);
}

static void test_glass(void) {
  pb_material g = tsc_glass(1.5f);
  pb_bsdf b;
  v3 wo = v3_make(0, 0, 1);
  setup(&g, wo, &b);
  pb_rng rng = pb_rng_make(5, 9, 2, 3);
  int refl = 0, absorbed = 0;
  enum { N = 200000 };
  for (int i = 0; i < N; ++i) {
    pb_bsdf_sample s;
    if (!pb_bsdf_sample_dir(&b, wo, pb_rng_f(&rng), pb_rng_f(&rng), pb_rng_f(&rng),
                            PB_IMPORTANCE, &s))
      absorbed++;
    else if (!s.transmit)
      refl++;
  }
  CHECK_EQ_INT(absorbed, 0);
  double f0 = pow(0.5 / 2.5, 2);
  printf("glass: reflected %.5f want %.5f\n", (double)refl / N, f0);
  CHECK_NEAR((double)refl / N, f0, 0.002);

  /* Snell: sin_t = sin_i / n entering; radiance scaled by 1/n^2. */
  v3 wo2 = dir_from_theta(40);
  setup(&g, wo2, &b);
  for (int i = 0; i < 64; ++i) {
    pb_bsdf_sample s;
    if (!pb_bsdf_sample_dir(&b, wo2, pb_rng_f(&rng), 0.5f, 0.5f, PB_RADIANCE, &s)) continue;
    if (!s.transmit) continue;
    double sin_t = sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y);
    CHECK_NEAR(sin_t, sin(40 * M_PI / 180) / 1.5, 1e-5);
    CHECK(s.wi.z < 0);
    CHECK_NEAR(s.weight.x, 1.0 / (1.5 * 1.5), 1e-5);
    break;
  }
  /* Leaving the glass past the critical angle: total internal reflection. */
  pb_surface surf;
  memset(&surf, 0, sizeof surf);
  surf.ng = surf.ns = v3_make(0, 0, 1);
  surf.front = 0; /* inside */
  surf.mat = &g;
  surf.color[0] = surf.color[1] = surf.color[2] = surf.color[3] = 1;
  v3 wo3 = dir_from_theta(60); /* asin(1/1.5) = 41.8 degrees */
  pb_bsdf_setup(&scene, &surf, wo3, NULL, &b);
  int tir = 0;
  for (int i = 0; i < 100; ++i) {
    pb_bsdf_sample s;
    if (pb_bsdf_sample_dir(&b, wo3, pb_rng_f(&rng), 0.5f, 0.5f, PB_RADIANCE, &s) &&
        !s.transmit && s.wi.z > 0)
      tir++;
  }
  CHECK_EQ_INT(tir, 100);
}

static void test_offsets(void) {
  const float mags[] = {0.0f, 1e-3f, 0.5f, 3.0f, 1e3f, 1e5f};
  v3 n = v3_norm(v3_make(0.2f, -0.5f, 0.8f));
  for (unsigned i = 0; i < sizeof mags / sizeof *mags; ++i)
    for (int sgn = -1; sgn <= 1; sgn += 2) {
      v3 p = v3_scale(v3_make(1.0f, 0.7f, -0.3f), (float)sgn * mags[i]);
      v3 q = pb_offset_ray(p, n), r = pb_offset_ray(p, v3_neg(n));
      double dq = ((double)q.x - p.x) * n.x + ((double)q.y - p.y) * n.y + ((double)q.z - p.z) * n.z;
      double dr = ((double)r.x - p.x) * n.x + ((double)r.y - p.y) * n.y + ((double)r.z - p.z) * n.z;
      CHECK(dq > 0);
      CHECK(dr < 0);
      /* Small: a few hundred ULPs, not a visible gap. */
      CHECK(fabs(dq) < 1e-4 * fmax(1.0, mags[i]));
    }
}

int main(void) {
  tsc_init(&scene);
  test_lambert();
  test_ggx();
  test_glass();
  test_offsets();
  pb_scene_destroy(&scene);
  return pbt_done();
}
