/* The emissive-triangle table (emitters.h). */
#include "scene/emitters.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

float pb_triangle_area(const pb_scene *s, uint32_t t) {
  const uint32_t *tri = s->triangles[t];
  const float *p0 = s->positions[tri[0]], *p1 = s->positions[tri[1]], *p2 = s->positions[tri[2]];
  float a[3], b[3];
  for (int i = 0; i < 3; ++i) a[i] = p1[i] - p0[i], b[i] = p2[i] - p0[i];
  float c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return 0.5f * sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

void pb_emitter_table_destroy(pb_emitter_table *t) {
  if (!t) return;
  free(t->prim);
  free(t->area);
  free(t->cdf);
  memset(t, 0, sizeof *t);
}

/* The emitted radiance a material's triangles average: the factor times its
 * texture's mean. tex_mean: per texture, filled on first use (w < 0). */
static void emitter_radiance(const pb_scene *s, const pb_material *m, float (*tex_mean)[4], float out[3]) {
  for (int c = 0; c < 3; ++c) out[c] = fmaxf(m->emissive[c], 0.0f);
  if (m->emissive_tex < 0 || (uint32_t)m->emissive_tex >= s->texture_count || !tex_mean) return;
  float *tm = tex_mean[m->emissive_tex];
  if (tm[3] < 0.0f) pb_texture_mean(&s->textures[m->emissive_tex], tm);
  for (int c = 0; c < 3; ++c) out[c] *= fmaxf(tm[c], 0.0f);
}

static float (*texture_means(const pb_scene *s))[4] {
  float (*tm)[4] = s->texture_count ? malloc(s->texture_count * sizeof *tm) : NULL;
  for (uint32_t i = 0; tm && i < s->texture_count; ++i) tm[i][3] = -1.0f;
  return tm;
}

void pb_emitter_flux(const pb_scene *s, double out[3]) {
  out[0] = out[1] = out[2] = 0.0;
  float (*tm)[4] = texture_means(s);
  for (uint32_t i = 0; i < s->triangle_count; ++i) {
    const pb_material *m = &s->materials[s->triangle_material[i]];
    if (!pb_material_is_emissive(m)) continue;
    float L[3];
    emitter_radiance(s, m, tm, L);
    double a = (double)pb_triangle_area(s, i) * M_PI * (m->double_sided ? 2.0 : 1.0);
    if (!(a > 0.0) || !isfinite(a)) continue;
    for (int c = 0; c < 3; ++c) out[c] += a * L[c];
  }
  free(tm);
  for (int c = 0; c < 3; ++c)
    if (!isfinite(out[c])) out[c] = 0.0;
}

pb_result pb_emitter_table_build(const pb_scene *s, pb_emitter_table *t) {
  memset(t, 0, sizeof *t);
  uint32_t n = 0;
  for (uint32_t i = 0; i < s->triangle_count; ++i)
    if (pb_material_is_emissive(&s->materials[s->triangle_material[i]])) n++;
  if (!n) return PB_OK;
  t->prim = malloc(n * sizeof *t->prim);
  t->area = malloc(n * sizeof *t->area);
  t->cdf = malloc((n + 1) * sizeof *t->cdf);
  if (!t->prim || !t->area || !t->cdf) {
    pb_emitter_table_destroy(t);
    return pb_fail(PB_ERR_NOMEM, "out of memory for %u emitters", n);
  }
  double total = 0.0;
  uint32_t k = 0;
  float (*tm)[4] = texture_means(s);
  for (uint32_t i = 0; i < s->triangle_count; ++i) {
    const pb_material *m = &s->materials[s->triangle_material[i]];
    if (!pb_material_is_emissive(m)) continue;
    float L[3];
    emitter_radiance(s, m, tm, L);
    float r = L[0], g = L[1], b = L[2];
    float lum = 0.2126f * r + 0.7152f * g + 0.0722f * b, mx = fmaxf(r, fmaxf(g, b));
    float area = pb_triangle_area(s, i);
    double w = (double)area * fmax(lum, 1e-3 * mx) * (m->double_sided ? 2.0 : 1.0);
    if (!(w > 0.0) || !isfinite(w) || !(area > 0.0f)) continue;
    t->prim[k] = i;
    t->area[k] = area;
    t->cdf[k] = total;
    total += w;
    k++;
  }
  free(tm);
  if (k == 0 || !(total > 0.0) || !isfinite(total)) {
    pb_emitter_table_destroy(t);
    return PB_OK;
  }
  for (uint32_t i = 0; i < k; ++i) t->cdf[i] /= total;
  t->cdf[k] = 1.0;
  t->count = k;
  return PB_OK;
}
