/* The world light: radiance lookup and the sampling table (world.h). */
#include "scene/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static const float *texel(const pb_world *w, int x, int y) {
  int W = (int)w->env_width, H = (int)w->env_height;
  x = ((x % W) + W) % W;             /* u is periodic */
  y = y < 0 ? 0 : (y >= H ? H - 1 : y); /* v stops at the poles */
  return w->env + 3 * ((size_t)y * (size_t)W + (size_t)x);
}

void pb_world_dir_to_uv(const pb_world *w, const float dir[3], float *u, float *v, float *sin_theta) {
  const float *M = w->env_to_map;
  float m[3];
  for (int r = 0; r < 3; ++r) m[r] = M[3 * r] * dir[0] + M[3 * r + 1] * dir[1] + M[3 * r + 2] * dir[2];
  float l = sqrtf(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
  float cz = l > 0 ? m[2] / l : 1.0f;
  cz = cz < -1.0f ? -1.0f : (cz > 1.0f ? 1.0f : cz);
  float uu = 0.5f - atan2f(m[1], m[0]) * (float)(0.5 / M_PI);
  uu -= floorf(uu);
  if (!(uu < 1.0f)) uu = 0.0f;
  *u = uu;
  *v = acosf(cz) * (float)(1.0 / M_PI);
  *sin_theta = sqrtf(fmaxf(0.0f, 1.0f - cz * cz));
}

void pb_world_uv_to_dir(const pb_world *w, float u, float v, float dir[3]) {
  float phi = (float)M_PI * (1.0f - 2.0f * u), theta = (float)M_PI * v;
  float st = sinf(theta);
  float m[3] = {st * cosf(phi), st * sinf(phi), cosf(theta)};
  const float *M = w->env_to_map; /* orthonormal: its inverse is its transpose */
  for (int c = 0; c < 3; ++c) dir[c] = M[c] * m[0] + M[3 + c] * m[1] + M[6 + c] * m[2];
}

void pb_world_radiance(const pb_world *w, const float dir[3], float out[3]) {
  if (!w->present) {
    out[0] = out[1] = out[2] = 0.0f;
    return;
  }
  if (!w->env) {
    memcpy(out, w->color, 3 * sizeof(float));
    return;
  }
  float u, v, st;
  pb_world_dir_to_uv(w, dir, &u, &v, &st);
  float fx = u * (float)w->env_width - 0.5f, fy = v * (float)w->env_height - 0.5f;
  float x0f = floorf(fx), y0f = floorf(fy);
  float ax = fx - x0f, ay = fy - y0f;
  int x0 = (int)x0f, y0 = (int)y0f;
  const float *a = texel(w, x0, y0), *b = texel(w, x0 + 1, y0), *c = texel(w, x0, y0 + 1),
              *d = texel(w, x0 + 1, y0 + 1);
  for (int k = 0; k < 3; ++k)
    out[k] = w->env_scale * ((a[k] * (1 - ax) + b[k] * ax) * (1 - ay) + (c[k] * (1 - ax) + d[k] * ax) * ay);
}

void pb_world_set_rotation(pb_world *w, const double e[3]) {
  double cx = cos(e[0]), sx = sin(e[0]), cy = cos(e[1]), sy = sin(e[1]), cz = cos(e[2]), sz = sin(e[2]);
  /* R = Rz(e2) Ry(e1) Rx(e0), row-major. */
  double R[9] = {cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx,
                 sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx,
                 -sy,     cy * sx,                cy * cx};
  /* C: glTF (x, y, z) -> Blender (x, -z, y). M = R C: column k of M is R
   * applied to C's column k: C e_x = e_x, C e_y = e_z, C e_z = -e_y. */
  for (int r = 0; r < 3; ++r) {
    w->env_to_map[3 * r + 0] = (float)R[3 * r + 0];
    w->env_to_map[3 * r + 1] = (float)R[3 * r + 2];
    w->env_to_map[3 * r + 2] = (float)-R[3 * r + 1];
  }
}

/* The mean over cell (x, y) of the bilinear radiance, channel k (before
 * env_scale): the [1 6 1]/8 filter in each direction. */
static float cell_mean(const pb_world *w, int x, int y, int k) {
  static const float f[3] = {0.125f, 0.75f, 0.125f};
  float s = 0.0f;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) s += f[dy + 1] * f[dx + 1] * texel(w, x + dx, y + dy)[k];
  return s;
}

void pb_world_update_integral(pb_world *w) {
  w->integral[0] = w->integral[1] = w->integral[2] = 0.0f;
  if (!w->present) return;
  if (!w->env) {
    for (int k = 0; k < 3; ++k) w->integral[k] = (float)(4.0 * M_PI) * w->color[k];
    return;
  }
  double sum[3] = {0, 0, 0};
  uint32_t W = w->env_width, H = w->env_height;
  double dphi = 2.0 * M_PI / W;
  for (uint32_t y = 0; y < H; ++y) {
    double omega = dphi * (cos(M_PI * y / H) - cos(M_PI * (y + 1) / H));
    for (uint32_t x = 0; x < W; ++x)
      for (int k = 0; k < 3; ++k) sum[k] += omega * cell_mean(w, (int)x, (int)y, k);
  }
  for (int k = 0; k < 3; ++k) w->integral[k] = (float)(sum[k] * w->env_scale);
}

void pb_world_dist_destroy(pb_world_dist *d) {
  if (!d) return;
  free(d->cond);
  free(d->marg);
  memset(d, 0, sizeof *d);
}

pb_result pb_world_dist_build(const pb_world *w, pb_world_dist *d) {
  memset(d, 0, sizeof *d);
  if (!w->present || !w->env) return PB_OK;
  uint32_t W = w->env_width, H = w->env_height;
  d->cond = malloc((size_t)H * (W + 1) * sizeof *d->cond);
  d->marg = malloc((size_t)(H + 1) * sizeof *d->marg);
  double *row = malloc((size_t)(W + 1) * sizeof *row);
  double *rows = malloc((size_t)(H + 1) * sizeof *rows);
  if (!d->cond || !d->marg || !row || !rows) {
    free(row);
    free(rows);
    pb_world_dist_destroy(d);
    return pb_fail(PB_ERR_NOMEM, "world: out of memory for the %ux%u sampling table", W, H);
  }
  rows[0] = 0.0;
  for (uint32_t y = 0; y < H; ++y) {
    double st = sin(M_PI * (y + 0.5) / H);
    row[0] = 0.0;
    for (uint32_t x = 0; x < W; ++x) {
      double m = (cell_mean(w, (int)x, (int)y, 0) + cell_mean(w, (int)x, (int)y, 1) + cell_mean(w, (int)x, (int)y, 2)) / 3.0;
      row[x + 1] = row[x] + (m > 0.0 && isfinite(m) ? m * st : 0.0);
    }
    float *c = d->cond + (size_t)y * (W + 1);
    double t = row[W];
    for (uint32_t x = 0; x <= W; ++x) c[x] = t > 0.0 ? (float)(row[x] / t) : (float)x / (float)W;
    c[W] = 1.0f;
    rows[y + 1] = rows[y] + t;
  }
  double total = rows[H];
  for (uint32_t y = 0; y <= H; ++y) d->marg[y] = total > 0.0 ? (float)(rows[y] / total) : (float)y / (float)H;
  d->marg[H] = 1.0f;
  free(row);
  free(rows);
  d->width = total > 0.0 ? W : 0;
  d->height = total > 0.0 ? H : 0;
  if (!(total > 0.0)) pb_world_dist_destroy(d); /* a black map: nothing to sample, uniform fallback */
  return PB_OK;
}

/* Largest i in [0, n) with cdf[i] <= u (cdf[0] = 0, n + 1 entries). */
static uint32_t find(const float *cdf, uint32_t n, float u) {
  uint32_t lo = 0, hi = n;
  while (hi - lo > 1) {
    uint32_t mid = (lo + hi) / 2;
    if (cdf[mid] <= u) lo = mid;
    else hi = mid;
  }
  return lo;
}

int pb_world_sample(const pb_world *w, const pb_world_dist *d, float u1, float u2, float dir[3], float *pdf) {
  if (!d->width) { /* constant world: uniform sphere */
    float z = 1.0f - 2.0f * u1, r = sqrtf(fmaxf(0.0f, 1.0f - z * z)), phi = 2.0f * (float)M_PI * u2;
    dir[0] = r * cosf(phi), dir[1] = r * sinf(phi), dir[2] = z;
    *pdf = (float)(0.25 / M_PI);
    return 1;
  }
  uint32_t W = d->width, H = d->height;
  uint32_t y = find(d->marg, H, u1);
  float py = d->marg[y + 1] - d->marg[y];
  if (!(py > 0.0f)) return 0;
  const float *c = d->cond + (size_t)y * (W + 1);
  uint32_t x = find(c, W, u2);
  float px = c[x + 1] - c[x];
  if (!(px > 0.0f)) return 0;
  float fy = fminf(fmaxf((u1 - d->marg[y]) / py, 0.0f), 0.99999994f);
  float fx = fminf(fmaxf((u2 - c[x]) / px, 0.0f), 0.99999994f);
  float u = ((float)x + fx) / (float)W, v = ((float)y + fy) / (float)H;
  pb_world_uv_to_dir(w, u, v, dir);
  float st = sinf((float)M_PI * v);
  if (!(st > 0.0f)) return 0;
  *pdf = px * py * (float)W * (float)H / (2.0f * (float)(M_PI * M_PI) * st);
  return 1;
}

float pb_world_pdf(const pb_world *w, const pb_world_dist *d, const float dir[3]) {
  if (!d->width) return (float)(0.25 / M_PI);
  float u, v, st;
  pb_world_dir_to_uv(w, dir, &u, &v, &st);
  if (!(st > 0.0f)) return 0.0f;
  uint32_t W = d->width, H = d->height;
  uint32_t x = (uint32_t)(u * (float)W), y = (uint32_t)(v * (float)H);
  if (x >= W) x = W - 1;
  if (y >= H) y = H - 1;
  float py = d->marg[y + 1] - d->marg[y];
  const float *c = d->cond + (size_t)y * (W + 1);
  float px = c[x + 1] - c[x];
  return px * py * (float)W * (float)H / (2.0f * (float)(M_PI * M_PI) * st);
}
