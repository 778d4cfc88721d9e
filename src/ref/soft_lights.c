/* Soft lights of the reference renderer: sampling and ray hits of sphere
 * lights, area lights and the soft sun, with Cycles 3.4's geometry and
 * strategies (kernel/light/light.h, light_common.h of Blender 3.4; scene.h
 * pb_light gives the emission each models). The GPU mirrors this file in
 * shaders/common/lights.glsl; tests compare the two. */
#include "ref/lights.h"

/* Below this solid angle [sr] a rectangle is sampled by area: Urena's
 * internal angles lose float precision there (the difference of four
 * angles of about pi/2 each). A deterministic function of the point and
 * the light, so light sampling and pb_soft_light_hit agree. */
#define PB_RECT_MIN_SOLID_ANGLE 1e-3f

/* Uniform point of the unit disc (polar map, area-preserving). */
static void unit_disc(float u1, float u2, float *x, float *y) {
  float r = sqrtf(u1), phi = 2.0f * PB_PI_F * u2;
  *x = r * cosf(phi);
  *y = r * sinf(phi);
}

/* Cycles 3.4's spread profile (scene.h): with a = (pi - max(spread, 1
 * degree)) / 2, max(0, 1 - tan(a) tan(t)) N(a) for the angle t between the
 * emission axis and the direction light leaves in (cos_t > 0). */
static void spread_params(const pb_light *l, float *tan_a, float *norm) {
  float s = l->spread > 0.0f ? l->spread : PB_PI_F;
  float a = 0.5f * (PB_PI_F - fmaxf(s, PB_PI_F / 180.0f));
  *tan_a = tanf(a);
  *norm = 2.0f / (2.0f + (2.0f * a - PB_PI_F) * *tan_a);
}
static float spread_factor(float tan_a, float norm, float cos_t) {
  if (!(cos_t > 0.0f)) return 0.0f;
  if (!(tan_a > 0.0f)) return 1.0f;
  float tan_t = sqrtf(fmaxf(0.0f, 1.0f - cos_t * cos_t)) / cos_t;
  return fmaxf((1.0f - tan_a * tan_t) * norm, 0.0f);
}

/* A rectangle: centre c, unit axes u, v, full widths lu, lv. */
typedef struct rect {
  v3 c, u, v;
  float lu, lv;
} rect;

/* The part of the area light's rectangle that its spread lets light p:
 * the square around the circle of radius t tan(spread / 2) about p's foot
 * on the light's plane (t: p's distance to the plane), clamped to the
 * rectangle (Cycles' light_spread_clamp_area_light). 0 when empty. */
static int rect_for(const pb_light *l, v3 p, float tan_a, rect *out) {
  rect r = {v3_load(l->position), v3_load(l->axis_u), v3_load(l->axis_v), l->size[0], l->size[1]};
  if (tan_a > 0.0f) {
    v3 n = v3_load(l->direction);
    float t = v3_dot(v3_sub(p, r.c), n);
    v3 foot = v3_madd(p, n, -t);
    float rad = fabsf(t) / tan_a;
    float cu = v3_dot(v3_sub(foot, r.c), r.u), cv = v3_dot(v3_sub(foot, r.c), r.v);
    float u0 = fmaxf(cu - rad, -0.5f * r.lu), u1 = fminf(cu + rad, 0.5f * r.lu);
    float v0 = fmaxf(cv - rad, -0.5f * r.lv), v1 = fminf(cv + rad, 0.5f * r.lv);
    if (!(u0 < u1) || !(v0 < v1)) return 0;
    r.c = v3_add(r.c, v3_add(v3_scale(r.u, 0.5f * (u0 + u1)), v3_scale(r.v, 0.5f * (v0 + v1))));
    r.lu = u1 - u0;
    r.lv = v1 - v0;
  }
  *out = r;
  return 1;
}

/* Urena et al. 2013, algorithm 1: the spherical rectangle of r seen from o.
 * Fills the local frame and returns its solid angle S; with sample != 0
 * also the point for (s, t) in [0, 1)^2, uniform in solid angle. */
static float spherical_rect(const rect *r, v3 o, int sample, float s, float t, v3 *q) {
  v3 x = r->u, y = r->v, z = v3_cross(x, y);
  v3 corner = v3_sub(v3_sub(r->c, v3_scale(x, 0.5f * r->lu)), v3_scale(y, 0.5f * r->lv));
  v3 d = v3_sub(corner, o);
  float z0 = v3_dot(d, z);
  if (z0 > 0.0f) z = v3_neg(z), z0 = -z0;
  float x0 = v3_dot(d, x), y0 = v3_dot(d, y), x1 = x0 + r->lu, y1 = y0 + r->lv;
  if (!(z0 < 0.0f)) return 0.0f; /* o on the light's plane */
  /* Normals of the planes through o and each edge (v00 v10, v10 v11, v11
   * v01, v01 v00), of which only the z parts are needed beyond the angles. */
  v3 v00 = v3_make(x0, y0, z0), v10 = v3_make(x1, y0, z0), v11 = v3_make(x1, y1, z0), v01 = v3_make(x0, y1, z0);
  v3 n0 = v3_norm(v3_cross(v00, v10)), n1 = v3_norm(v3_cross(v10, v11));
  v3 n2 = v3_norm(v3_cross(v11, v01)), n3 = v3_norm(v3_cross(v01, v00));
  float g0 = acosf(fminf(fmaxf(-v3_dot(n0, n1), -1.0f), 1.0f));
  float g1 = acosf(fminf(fmaxf(-v3_dot(n1, n2), -1.0f), 1.0f));
  float g2 = acosf(fminf(fmaxf(-v3_dot(n2, n3), -1.0f), 1.0f));
  float g3 = acosf(fminf(fmaxf(-v3_dot(n3, n0), -1.0f), 1.0f));
  float b0 = n0.z, b1 = n2.z, k = 2.0f * PB_PI_F - g2 - g3;
  float S = g0 + g1 - k;
  if (!sample || !(S > 0.0f)) return S;
  float au = s * S + k;
  float fu = (cosf(au) * b0 - b1) / sinf(au);
  float cu = copysignf(1.0f, fu) / sqrtf(fu * fu + b0 * b0);
  cu = fminf(fmaxf(cu, -1.0f), 1.0f);
  float xu = -(cu * z0) / fmaxf(sqrtf(1.0f - cu * cu), 1e-7f);
  xu = fminf(fmaxf(xu, x0), x1);
  float dd = sqrtf(xu * xu + z0 * z0);
  float h0 = y0 / sqrtf(dd * dd + y0 * y0), h1 = y1 / sqrtf(dd * dd + y1 * y1);
  float hv = h0 + t * (h1 - h0), hv2 = hv * hv;
  float yv = hv2 < 1.0f - 1e-6f ? hv * dd / sqrtf(1.0f - hv2) : y1;
  *q = v3_add(o, v3_add(v3_add(v3_scale(x, xu), v3_scale(y, yv)), v3_scale(z, z0)));
  return S;
}

static float sun_tan(const pb_light *l) { return tanf(0.5f * l->angle); }

/* Cycles 4.x's sphere light (kernel/light/point.h, spot.h with is_sphere):
 * from a point at distance d > r from the centre the sphere subtends the
 * cone of half-angle asin(r / d), sampled uniformly in solid angle; from
 * inside, every direction is (uniform sphere; Cycles samples the cosine
 * hemisphere there when it knows the normal, the same expectation). A
 * spot's falloff applies outside only. 1 - cos of the cone's half-angle,
 * exact without cancellation for small r / d: */
static float sphere_one_minus_cos(float r2, float d2) {
  float s2 = r2 / d2;
  return s2 / (1.0f + sqrtf(fmaxf(0.0f, 1.0f - s2)));
}

/* Radiance of a point or spot light of radius r (its disc or its sphere)
 * leaving in direction w toward the lit point: I / (pi r^2), a spot's
 * falloff outside the sphere. */
static v3 sphere_light_radiance(const pb_light *l, v3 w, int inside) {
  float k = l->intensity / (PB_PI_F * l->radius * l->radius);
  if (l->type == PB_LIGHT_SPOT && !inside) k *= pb_spot_factor(l, v3_dot(v3_norm(v3_load(l->direction)), w));
  return v3_scale(v3_load(l->color), k);
}

static int sphere_light_sample(const pb_light *l, v3 p, float u1, float u2, pb_light_sample *out) {
  v3 axis = v3_sub(v3_load(l->position), p);
  float d2 = v3_dot(axis, axis), r2 = l->radius * l->radius, d = sqrtf(d2);
  int inside = !(d2 > r2);
  v3 wi;
  float cos_t, pdf;
  if (!inside) {
    axis = v3_scale(axis, 1.0f / d);
    float omc = sphere_one_minus_cos(r2, d2), x = u1 * omc;
    cos_t = 1.0f - x;
    float sin_t = sqrtf(fmaxf(0.0f, x * (2.0f - x))), phi = 2.0f * PB_PI_F * u2;
    v3 t, b;
    v3_basis(axis, &t, &b);
    wi = v3_norm(v3_add(v3_scale(axis, cos_t), v3_add(v3_scale(t, sin_t * cosf(phi)), v3_scale(b, sin_t * sinf(phi)))));
    pdf = 1.0f / (2.0f * PB_PI_F * omc);
  } else {
    float z = 1.0f - 2.0f * u1, s = sqrtf(fmaxf(0.0f, 1.0f - z * z)), phi = 2.0f * PB_PI_F * u2;
    wi = v3_make(s * cosf(phi), s * sinf(phi), z);
    cos_t = d > 0.0f ? v3_dot(wi, v3_scale(axis, 1.0f / d)) : 0.0f;
    pdf = 1.0f / (4.0f * PB_PI_F);
  }
  /* Law of cosines: the near intersection from outside, the exit from inside. */
  float h = sqrtf(fmaxf(0.0f, r2 - d2 + d2 * cos_t * cos_t));
  out->wi = wi;
  out->dist = inside ? d * cos_t + h : d * cos_t - h;
  out->pdf = pdf;
  out->L = sphere_light_radiance(l, v3_neg(wi), inside);
  return out->dist > 0.0f && pdf > 0.0f && isfinite(pdf) && !v3_is_zero(out->L);
}

static int sphere_light_hit(const pb_light *l, v3 o, v3 d, float tmax, float *t_out, v3 *L, float *pdf) {
  v3 oc = v3_sub(o, v3_load(l->position));
  float r2 = l->radius * l->radius, b = v3_dot(oc, d), d2 = v3_dot(oc, oc), cc = d2 - r2;
  float disc = b * b - cc;
  if (!(disc >= 0.0f)) return 0;
  float sq = sqrtf(disc), t;
  int inside = !(cc > 0.0f);
  if (!inside) {
    if (!(b < 0.0f)) return 0;  /* the sphere is behind */
    t = cc / (sq - b);          /* the near root, without cancellation */
    *pdf = 1.0f / (2.0f * PB_PI_F * sphere_one_minus_cos(r2, d2));
  } else {
    t = sq - b;
    *pdf = 1.0f / (4.0f * PB_PI_F);
  }
  if (!(t > 0.0f) || !(t < tmax)) return 0;
  *t_out = t;
  *L = sphere_light_radiance(l, v3_neg(d), inside);
  return isfinite(*pdf) && !v3_is_zero(*L);
}

int pb_soft_light_sample(const pb_light *l, v3 p, float u1, float u2, pb_light_sample *out) {
  v3 col = v3_load(l->color);
  if (l->type == PB_LIGHT_DIRECTIONAL) {
    /* The disc of radius R = tan(angle / 2) at unit distance. */
    v3 axis = v3_neg(v3_norm(v3_load(l->direction))), t, b;
    v3_basis(axis, &t, &b);
    float R = sun_tan(l), x, y;
    unit_disc(u1, u2, &x, &y);
    v3 wi = v3_norm(v3_add(axis, v3_add(v3_scale(t, R * x), v3_scale(b, R * y))));
    float c = v3_dot(wi, axis);
    float pdf = 1.0f / (PB_PI_F * R * R * c * c * c);
    out->wi = wi;
    out->dist = INFINITY;
    out->pdf = pdf;
    out->L = v3_scale(col, l->intensity * pdf);
    return pdf > 0.0f && isfinite(pdf);
  }
  if (l->type == PB_LIGHT_AREA) {
    v3 n = v3_load(l->direction), c = v3_load(l->position);
    if (!(v3_dot(v3_sub(p, c), n) > 0.0f)) return 0; /* behind the one-sided light */
    float tan_a, norm;
    spread_params(l, &tan_a, &norm);
    v3 q;
    float pdf;
    if (l->shape == PB_AREA_RECTANGLE) {
      rect r;
      if (!rect_for(l, p, tan_a, &r)) return 0;
      float S = spherical_rect(&r, p, 0, 0, 0, NULL);
      if (S >= PB_RECT_MIN_SOLID_ANGLE) {
        spherical_rect(&r, p, 1, u1, u2, &q);
        pdf = 1.0f / S;
      } else {
        q = v3_add(r.c, v3_add(v3_scale(r.u, (u1 - 0.5f) * r.lu), v3_scale(r.v, (u2 - 0.5f) * r.lv)));
        pdf = -1.0f / (r.lu * r.lv); /* area density, converted below */
      }
    } else {
      float x, y;
      unit_disc(u1, u2, &x, &y);
      q = v3_add(c, v3_add(v3_scale(v3_load(l->axis_u), 0.5f * l->size[0] * x),
                           v3_scale(v3_load(l->axis_v), 0.5f * l->size[1] * y)));
      pdf = -1.0f / pb_light_area(l);
    }
    v3 d = v3_sub(q, p);
    float d2 = v3_dot(d, d);
    if (!(d2 > 0.0f)) return 0;
    float dl = sqrtf(d2);
    v3 wi = v3_scale(d, 1.0f / dl);
    float cos_l = -v3_dot(wi, n);
    if (!(cos_l > 0.0f)) return 0;
    if (pdf < 0.0f) pdf = -pdf * d2 / cos_l;
    float f = spread_factor(tan_a, norm, cos_l);
    if (!(f > 0.0f)) return 0;
    out->wi = wi;
    out->dist = dl;
    out->pdf = pdf;
    out->L = v3_scale(col, l->intensity * f);
    return pdf > 0.0f && isfinite(pdf);
  }
  if (l->sphere) return sphere_light_sample(l, p, u1, u2, out);
  /* Soft light (Cycles 3.4, and 4.x's Soft Falloff): uniform on the disc of
   * radius r through the centre, facing p. */
  v3 c = v3_load(l->position), nl = v3_sub(p, c);
  float dc = v3_len(nl);
  if (!(dc > 0.0f)) return 0;
  nl = v3_scale(nl, 1.0f / dc);
  v3 t, b;
  v3_basis(nl, &t, &b);
  float x, y;
  unit_disc(u1, u2, &x, &y);
  v3 q = v3_add(c, v3_add(v3_scale(t, l->radius * x), v3_scale(b, l->radius * y)));
  v3 d = v3_sub(q, p);
  float d2 = v3_dot(d, d);
  if (!(d2 > 0.0f)) return 0;
  float dl = sqrtf(d2);
  v3 wi = v3_scale(d, 1.0f / dl);
  float cos_l = -v3_dot(wi, nl);
  if (!(cos_l > 0.0f)) return 0;
  out->wi = wi;
  out->dist = dl;
  out->pdf = d2 / (cos_l * PB_PI_F * l->radius * l->radius);
  out->L = sphere_light_radiance(l, v3_neg(wi), 0);
  return out->pdf > 0.0f && isfinite(out->pdf) && !v3_is_zero(out->L);
}

int pb_soft_light_hit(const pb_light *l, v3 o, v3 d, float tmax, float *t_out, v3 *L, float *pdf) {
  v3 col = v3_load(l->color);
  if (l->type == PB_LIGHT_DIRECTIONAL) {
    if (tmax < INFINITY) return 0;
    v3 axis = v3_neg(v3_norm(v3_load(l->direction)));
    float c = v3_dot(d, axis);
    if (!(c >= cosf(0.5f * l->angle)) || !(c > 0.0f)) return 0;
    float R = sun_tan(l);
    *pdf = 1.0f / (PB_PI_F * R * R * c * c * c);
    *L = v3_scale(col, l->intensity * *pdf);
    *t_out = INFINITY;
    return isfinite(*pdf);
  }
  if (l->type == PB_LIGHT_AREA) {
    v3 n = v3_load(l->direction), c = v3_load(l->position);
    float dn = v3_dot(d, n);
    if (!(dn < 0.0f)) return 0; /* one-sided: only rays against the emission */
    float t = v3_dot(v3_sub(c, o), n) / dn;
    if (!(t > 0.0f) || !(t < tmax)) return 0;
    v3 q = v3_madd(o, d, t), rq = v3_sub(q, c);
    float x = v3_dot(rq, v3_load(l->axis_u)) / (0.5f * l->size[0]), y = v3_dot(rq, v3_load(l->axis_v)) / (0.5f * l->size[1]);
    if (l->shape == PB_AREA_RECTANGLE ? (fabsf(x) > 1.0f || fabsf(y) > 1.0f) : (x * x + y * y > 1.0f)) return 0;
    float tan_a, norm;
    spread_params(l, &tan_a, &norm);
    float cos_l = -dn, f = spread_factor(tan_a, norm, cos_l);
    if (!(f > 0.0f)) return 0;
    float p;
    if (l->shape == PB_AREA_RECTANGLE) {
      rect r;
      if (!rect_for(l, o, tan_a, &r)) return 0;
      /* The clamped rectangle holds every point the spread lets reach o. */
      float S = spherical_rect(&r, o, 0, 0, 0, NULL);
      p = S >= PB_RECT_MIN_SOLID_ANGLE ? 1.0f / S : t * t / (cos_l * r.lu * r.lv);
    } else {
      p = t * t / (cos_l * pb_light_area(l));
    }
    *t_out = t;
    *L = v3_scale(col, l->intensity * f);
    *pdf = p;
    return p > 0.0f && isfinite(p);
  }
  if (l->sphere) return sphere_light_hit(l, o, d, tmax, t_out, L, pdf);
  /* Soft light: the disc through the centre facing o. */
  v3 c = v3_load(l->position), nl = v3_sub(o, c);
  float dc = v3_len(nl);
  if (!(dc > 0.0f)) return 0;
  nl = v3_scale(nl, 1.0f / dc);
  float dn = v3_dot(d, nl);
  if (!(dn < 0.0f)) return 0;
  float t = -dc / dn; /* the plane through c with normal nl: (o + t d - c) . nl = 0 */
  if (!(t > 0.0f) || !(t < tmax)) return 0;
  v3 q = v3_madd(o, d, t), rq = v3_sub(q, c);
  if (v3_dot(rq, rq) > l->radius * l->radius) return 0;
  *t_out = t;
  *L = sphere_light_radiance(l, v3_neg(d), 0);
  *pdf = t * t / (-dn * PB_PI_F * l->radius * l->radius);
  return *pdf > 0.0f && isfinite(*pdf) && !v3_is_zero(*L);
}

int pb_area_light_emit(const pb_light *l, float u1, float u2, float u3, float u4, v3 *o, v3 *d, float *weight) {
  v3 c = v3_load(l->position), n = v3_load(l->direction), au = v3_load(l->axis_u), av = v3_load(l->axis_v);
  float x, y;
  if (l->shape == PB_AREA_RECTANGLE) {
    x = u1 - 0.5f, y = u2 - 0.5f;
  } else {
    unit_disc(u1, u2, &x, &y);
    x *= 0.5f, y *= 0.5f;
  }
  *o = v3_add(c, v3_add(v3_scale(au, x * l->size[0]), v3_scale(av, y * l->size[1])));
  float tan_a, norm;
  spread_params(l, &tan_a, &norm);
  /* Cone of half-angle pi/2 - a, cosine-weighted: sin^2 t = u3 sin^2(pi/2 - a). */
  float s2max = tan_a > 0.0f ? 1.0f / (1.0f + tan_a * tan_a) : 1.0f; /* cos^2 a */
  float s2 = u3 * s2max, ct = sqrtf(fmaxf(0.0f, 1.0f - s2)), st = sqrtf(s2), phi = 2.0f * PB_PI_F * u4;
  *d = v3_norm(v3_add(v3_scale(n, ct), v3_add(v3_scale(au, st * cosf(phi)), v3_scale(av, st * sinf(phi)))));
  *weight = pb_light_area(l) * PB_PI_F * s2max * spread_factor(tan_a, norm, ct);
  return *weight > 0.0f;
}

v3 pb_sphere_light_origin(const pb_light *l, v3 d, float u1, float u2) {
  v3 t, b;
  v3_basis(d, &t, &b);
  float x, y;
  unit_disc(u1, u2, &x, &y);
  float h = sqrtf(fmaxf(0.0f, 1.0f - x * x - y * y));
  return v3_add(v3_load(l->position), v3_scale(v3_add(v3_add(v3_scale(t, x), v3_scale(b, y)), v3_scale(d, h)), l->radius));
}
