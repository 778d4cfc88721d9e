/* The environment maps of the image-space photon tracer (image_maps.h;
 * seed 003 sections 3-5). */
#include "render/photon/image_maps.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "render/scene/passes.h"
#include "shaders/image_maps.spv.h"
#include "shaders/image_maps_rq.spv.h"
#include "shaders/image_maps_query.spv.h"
#include "shaders/image_maps_touch.spv.h"

struct pb_image_maps {
  pb_image_maps_desc d;
  const pb_gpu_scene *gs;
  pb_gpu_pipeline render_pipe, select_pipe, query_pipe, touch_pipe;
  pb_gpu_buffer touch;                  /* pb_gpu_image_touch */
  pb_gpu_buffer maps, texels;           /* the k maps */
  pb_gpu_buffer cand_maps, cand_texels; /* the candidates' low-resolution maps */
  pb_gpu_buffer rays, hits, counts;     /* queries */
  uint32_t query_capacity;
  float bmin[3], bmax[3];               /* the scene's box, padded */
  float radius;                         /* its bounding radius */
  float cand[PB_IMAGE_MAPS_MAX_CANDIDATES][3];
  uint32_t ncand;
  uint32_t sel[PB_IMAGE_MAPS_MAX + 1];  /* the centres: indices into cand (k + 1 during a swap step) */
  uint32_t nsel;
  pb_gpu_image_texel *host_cand;        /* ncand x per_cand texels */
  float *area;                          /* eq. 1 area of every candidate texel (0: no surface, back face or
                                           a candidate inside an object) */
  uint8_t *seen;                        /* centres of C that see the candidate texel's point */
  uint32_t updates;
  float (*pose)[3];                     /* the vertex positions the maps were rendered of */
  uint32_t pose_count;
  pb_image_maps_stats st;
};

static const uint32_t SELECT_PER = 6u * PB_IMAGE_MAPS_SELECT_RESOLUTION * PB_IMAGE_MAPS_SELECT_RESOLUTION;

/* ---- host ports of common/image_maps.glsl ---------------------------------- */

uint32_t pb_cube_texel(const float w[3], uint32_t res) {
  float a[3] = {fabsf(w[0]), fabsf(w[1]), fabsf(w[2])};
  uint32_t ax = (a[0] >= a[1] && a[0] >= a[2]) ? 0u : (a[1] >= a[2] ? 1u : 2u);
  float m = fmaxf(a[ax], 1e-30f);
  uint32_t face = 2u * ax + (w[ax] < 0.0f ? 1u : 0u);
  float s = w[(ax + 1) % 3] / m, t = w[(ax + 2) % 3] / m;
  float fr = (float)res;
  float fi = floorf((s * 0.5f + 0.5f) * fr), fj = floorf((t * 0.5f + 0.5f) * fr);
  uint32_t i = (uint32_t)fminf(fmaxf(fi, 0.0f), fr - 1.0f), j = (uint32_t)fminf(fmaxf(fj, 0.0f), fr - 1.0f);
  return (face * res + j) * res + i;
}

void pb_cube_dir(uint32_t idx, uint32_t res, float out[3]) {
  uint32_t i = idx % res, j = (idx / res) % res, face = idx / (res * res);
  uint32_t ax = face / 2u;
  float sg = (face % 2u) == 0u ? 1.0f : -1.0f;
  float s = ((float)i + 0.5f) / (float)res * 2.0f - 1.0f, t = ((float)j + 0.5f) / (float)res * 2.0f - 1.0f;
  float w[3] = {0, 0, 0};
  w[ax] = sg;
  w[(ax + 1) % 3] = s;
  w[(ax + 2) % 3] = t;
  float l = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  for (int c = 0; c < 3; ++c) out[c] = w[c] / l;
}

uint32_t pb_image_classify(const float x[3], const float r[3], const float p[3], float epsilon) {
  float q[3] = {p[0] - x[0], p[1] - x[1], p[2] - x[2]};
  float l = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  if (!(l > 0.0f)) return PB_IMAGE_TYPE_B;
  float e = 1.0f - (q[0] * r[0] + q[1] * r[1] + q[2] * r[2]) / l; /* eq. 2 */
  return e <= epsilon ? PB_IMAGE_TYPE_D : PB_IMAGE_TYPE_B;
}

/* Eq. 1 (appendix A): a texel of a cube face seen from v at distance 1 from
 * a projection plane of half side r = 1 covers A0 = 4 / N of it (N = res^2
 * texels per face), and the surface area
 *   A(p) = A0 ((x - v).r_f)^3 / (r^2 (v - x).n),
 * r_f the face's forward axis. |cos alpha| = |(v - x).n| / |v - x| is
 * clamped at 0.1 (84 degrees): eq. 1 is first order in the texel's size and
 * unbounded at grazing incidence, where a texel's true footprint is set by
 * the surface's extent, so a few grazing texels would otherwise decide the
 * selection. */
double pb_image_texel_area(const float v[3], const pb_gpu_image_texel *t, uint32_t idx, uint32_t res) {
  if (t->prim == PB_GPU_MISS) return 0.0;
  uint32_t face = idx / (res * res), ax = face / 2u;
  double q[3] = {t->position[0] - v[0], t->position[1] - v[1], t->position[2] - v[2]};
  double l = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  if (!(l > 0.0)) return 0.0;
  double fwd = fabs(q[ax]);
  double cosa = fabs(q[0] * t->normal[0] + q[1] * t->normal[1] + q[2] * t->normal[2]) / l;
  if (cosa < 0.1) cosa = 0.1;
  return 4.0 / ((double)res * res) * fwd * fwd * fwd / (cosa * l);
}

/* ---- selection (section 4) ------------------------------------------------- */

static uint64_t splitmix(uint64_t *s) {
  uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

/* Candidate c sees point x (shadow mapping with c's low-resolution map,
 * 4.2): x is no farther than the map's surface in its direction, within a
 * bias of 5 % of that distance plus 1 % of the scene radius (the depth of
 * a 32^2 texel varies across it by about its width, 2/32 ~ 6 % of the
 * distance, more on slanted surfaces). A texel that saw nothing hides
 * nothing. */
static int sees(const pb_image_maps *m, uint32_t c, const float x[3]) {
  const float *v = m->cand[c];
  float w[3] = {x[0] - v[0], x[1] - v[1], x[2] - v[2]};
  const pb_gpu_image_texel *t =
      &m->host_cand[(size_t)c * SELECT_PER + pb_cube_texel(w, PB_IMAGE_MAPS_SELECT_RESOLUTION)];
  if (t->prim == PB_GPU_MISS) return 1;
  float dx = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  float q[3] = {t->position[0] - v[0], t->position[1] - v[1], t->position[2] - v[2]};
  float dm = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  return dx <= 1.05f * dm + 0.01f * m->radius;
}

/* Adds (+1) or removes (-1) centre c from the counts of every candidate
 * texel's point. */
static void account(pb_image_maps *m, uint32_t c, int sign) {
  for (uint32_t v = 0; v < m->ncand; ++v)
    for (uint32_t p = 0; p < SELECT_PER; ++p) {
      size_t i = (size_t)v * SELECT_PER + p;
      if (m->area[i] > 0.0f && sees(m, c, m->host_cand[i].position)) m->seen[i] = (uint8_t)(m->seen[i] + sign);
    }
}

/* A(v|C) for v not in C (the texels of v's map no centre sees), or
 * A(v|C - {v}) for v in C (those only v sees). */
static double new_coverage(const pb_image_maps *m, uint32_t v, int in_c) {
  double a = 0.0;
  for (uint32_t p = 0; p < SELECT_PER; ++p) {
    size_t i = (size_t)v * SELECT_PER + p;
    if (m->area[i] > 0.0f && m->seen[i] == (in_c ? 1u : 0u)) a += m->area[i];
  }
  return a;
}

static int selected(const pb_image_maps *m, uint32_t v) {
  for (uint32_t i = 0; i < m->nsel; ++i)
    if (m->sel[i] == v) return 1;
  return 0;
}

static uint32_t best_new(const pb_image_maps *m) {
  uint32_t best = UINT32_MAX;
  double ba = -1.0;
  for (uint32_t v = 0; v < m->ncand; ++v) {
    if (selected(m, v)) continue;
    double a = new_coverage(m, v, 0);
    if (a > ba) ba = a, best = v;
  }
  return best;
}

/* One update step (4.1): the best unselected candidate joins C, then the
 * centre of C with the least A(v|C - {v}) leaves. Returns 1 when C changed. */
static int swap_step(pb_image_maps *m) {
  uint32_t u = best_new(m);
  if (u == UINT32_MAX) return 0;
  m->sel[m->nsel++] = u;
  account(m, u, +1);
  uint32_t worst = 0;
  double wa = INFINITY;
  for (uint32_t i = 0; i < m->nsel; ++i) {
    double a = new_coverage(m, m->sel[i], 1);
    if (a < wa) wa = a, worst = i;
  }
  uint32_t w = m->sel[worst];
  account(m, w, -1);
  /* Keep the order of the others; the newcomer takes the leaver's slot. */
  if (worst != m->nsel - 1) m->sel[worst] = m->sel[m->nsel - 1];
  m->nsel--;
  return w != u;
}

/* Renders maps [first, first + count) of `pipe` at `res`, own submission. */
static pb_result render(pb_gpu *g, const pb_gpu_pipeline *pipe, uint32_t first, uint32_t count, uint32_t res) {
  pb_gpu_image_maps_push push = {.first_map = first, .map_count = count, .resolution = res};
  pb_result r = pb_gpu_begin(g);
  if (r != PB_OK) return r;
  r = pb_gpu_dispatch(g, pipe, &push, (uint64_t)count * 6u * res * res);
  pb_result rs = pb_gpu_submit(g);
  return r != PB_OK ? r : rs;
}

static pb_result upload_maps(pb_gpu *g, pb_gpu_buffer *buf, const pb_image_maps *m, const float (*centres)[3],
                             uint32_t count, uint32_t res) {
  uint8_t block[sizeof(pb_gpu_image_maps_info) + PB_IMAGE_MAPS_MAX_CANDIDATES * sizeof(pb_gpu_image_map)];
  pb_gpu_image_maps_info info;
  memset(&info, 0, sizeof info);
  info.count = count;
  info.resolution = res;
  info.march_steps = m->d.march_steps;
  info.secant_steps = m->d.secant_steps;
  info.epsilon = m->d.epsilon;
  /* Rays start 1e-4 R from their origin: past the tracer's own offset
   * (pb_offset_ray), never past a real neighbour. */
  info.start_offset = 1e-4f * m->radius;
  memcpy(info.bounds_min, m->bmin, sizeof m->bmin);
  memcpy(info.bounds_max, m->bmax, sizeof m->bmax);
  memcpy(block, &info, sizeof info);
  for (uint32_t i = 0; i < count; ++i) {
    pb_gpu_image_map e;
    memset(&e, 0, sizeof e);
    memcpy(e.center, centres[i], sizeof e.center);
    e.first = i * 6u * res * res;
    memcpy(block + sizeof info + i * sizeof e, &e, sizeof e);
  }
  return pb_gpu_buffer_upload(g, buf, 0, block, sizeof info + count * sizeof(pb_gpu_image_map));
}

static void scene_box(pb_image_maps *m, const pb_scene *s) {
  float d2 = 0.0f;
  for (int c = 0; c < 3; ++c) {
    float e = s->bounds_max[c] - s->bounds_min[c];
    d2 += e * e;
  }
  m->radius = 0.5f * sqrtf(d2);
  if (!(m->radius > 1e-6f) || !isfinite(m->radius)) m->radius = 1e-6f;
  for (int c = 0; c < 3; ++c) {
    m->bmin[c] = s->bounds_min[c] - 1e-3f * m->radius; /* a ray along a wall stays inside */
    m->bmax[c] = s->bounds_max[c] + 1e-3f * m->radius;
  }
}

/* The candidates' maps rendered and read back, eq. 1's areas, and the
 * counts of the current C. */
static pb_result prepare_selection(pb_gpu *g, pb_image_maps *m) {
  pb_result r;
  if ((r = upload_maps(g, &m->cand_maps, m, (const float(*)[3])m->cand, m->ncand, PB_IMAGE_MAPS_SELECT_RESOLUTION)) !=
          PB_OK ||
      (r = render(g, &m->select_pipe, 0, m->ncand, PB_IMAGE_MAPS_SELECT_RESOLUTION)) != PB_OK ||
      (r = pb_gpu_buffer_download(g, &m->cand_texels, 0, m->host_cand,
                                  (uint64_t)m->ncand * SELECT_PER * sizeof *m->host_cand)) != PB_OK)
    return r;
  for (uint32_t v = 0; v < m->ncand; ++v) {
    /* A candidate inside an object sees mostly back faces: it covers
     * nothing (the scene's surfaces face outwards from solid objects). */
    uint32_t back = 0, hit = 0;
    for (uint32_t p = 0; p < SELECT_PER; ++p) {
      const pb_gpu_image_texel *t = &m->host_cand[(size_t)v * SELECT_PER + p];
      if (t->prim == PB_GPU_MISS) continue;
      hit++;
      float q[3] = {m->cand[v][0] - t->position[0], m->cand[v][1] - t->position[1], m->cand[v][2] - t->position[2]};
      if (q[0] * t->normal[0] + q[1] * t->normal[1] + q[2] * t->normal[2] < 0.0f) back++;
    }
    int inside = hit > 0 && 2 * back > hit;
    for (uint32_t p = 0; p < SELECT_PER; ++p) {
      size_t i = (size_t)v * SELECT_PER + p;
      m->area[i] = inside ? 0.0f
                          : (float)pb_image_texel_area(m->cand[v], &m->host_cand[i], p, PB_IMAGE_MAPS_SELECT_RESOLUTION);
    }
  }
  memset(m->seen, 0, (size_t)m->ncand * SELECT_PER);
  for (uint32_t i = 0; i < m->nsel; ++i) account(m, m->sel[i], +1);
  m->st.selections++;
  return PB_OK;
}

static void coverage_stats(pb_image_maps *m) {
  double all = 0.0, un = 0.0;
  for (size_t i = 0; i < (size_t)m->ncand * SELECT_PER; ++i) {
    all += m->area[i];
    if (m->seen[i] == 0) un += m->area[i];
  }
  m->st.coverage_m2 = all - un;
  m->st.uncovered_m2 = un;
}

/* Renders maps [first, first + count) (all: 0, nsel), after uploading
 * every centre (the others' entries are unchanged). */
static pb_result render_maps(pb_gpu *g, pb_image_maps *m, uint32_t first, uint32_t count) {
  double t0 = pb_time_now();
  float c[PB_IMAGE_MAPS_MAX][3];
  for (uint32_t i = 0; i < m->nsel; ++i) memcpy(c[i], m->cand[m->sel[i]], sizeof c[i]);
  pb_result r = upload_maps(g, &m->maps, m, (const float(*)[3])c, m->nsel, m->d.resolution);
  if (r == PB_OK) r = render(g, &m->render_pipe, first, count, m->d.resolution);
  if (count == m->nsel) m->st.map_renders++;
  m->st.maps_rendered += count;
  m->st.render_ms = (pb_time_now() - t0) * 1e3;
  return r;
}

/* Remembers the pose the maps show; 1 when it differs from the last one
 * (a vertex moved, or the first call). box (may be NULL): the bounds of
 * every triangle with a moved vertex, at its old and its new positions
 * (all of the scene's on the first call or a new vertex count). */
static int pose_changed(pb_image_maps *m, const pb_scene *s, float box[2][3]) {
  size_t bytes = (size_t)s->vertex_count * sizeof *m->pose;
  if (m->pose && m->pose_count == s->vertex_count && (!bytes || memcmp(m->pose, s->positions, bytes) == 0))
    return 0;
  if (box) {
    for (int c = 0; c < 3; ++c) box[0][c] = INFINITY, box[1][c] = -INFINITY;
    int all = !m->pose || m->pose_count != s->vertex_count;
    for (uint32_t t = 0; t < s->triangle_count; ++t) {
      const uint32_t *v = s->triangles[t];
      int mv = all;
      for (int k = 0; k < 3 && !mv; ++k) mv = memcmp(m->pose[v[k]], s->positions[v[k]], sizeof *m->pose) != 0;
      if (!mv) continue;
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) {
          float a = s->positions[v[k]][c], b = all ? a : m->pose[v[k]][c];
          box[0][c] = fminf(box[0][c], fminf(a, b));
          box[1][c] = fmaxf(box[1][c], fmaxf(a, b));
        }
    }
  }
  float(*p)[3] = m->pose_count == s->vertex_count && m->pose ? m->pose : realloc(m->pose, bytes ? bytes : 1);
  if (p) {
    m->pose = p;
    m->pose_count = s->vertex_count;
    if (bytes) memcpy(m->pose, s->positions, bytes);
  }
  return 1;
}

static pb_result bind_render(pb_gpu *g, pb_gpu_pipeline *p, const pb_gpu_scene *gs, pb_gpu_buffer *maps,
                             pb_gpu_buffer *texels) {
  const pb_gpu_buffer *b[PB_IMAGE_BIND_COUNT] = {
      [PB_IMAGE_BIND_NODES] = &gs->nodes,       [PB_IMAGE_BIND_TRIS] = &gs->tris,
      [PB_IMAGE_BIND_INDICES] = &gs->indices,   [PB_IMAGE_BIND_POSITIONS] = &gs->positions,
      [PB_IMAGE_BIND_TRI_MATERIAL] = &gs->tri_material, [PB_IMAGE_BIND_MAPS] = maps,
      [PB_IMAGE_BIND_TEXELS] = texels,          [PB_IMAGE_BIND_RAYS] = maps,
      [PB_IMAGE_BIND_HITS] = maps,              [PB_IMAGE_BIND_COUNTS] = maps};
  return pb_kernel_bind(g, p, b, PB_IMAGE_BIND_COUNT, pb_gpu_scene_accel(gs));
}

pb_result pb_image_maps_create(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const pb_image_maps_desc *desc,
                               pb_image_maps **out) {
  *out = NULL;
  pb_image_maps_desc d = desc ? *desc : (pb_image_maps_desc){0};
  if (!d.count) d.count = PB_IMAGE_MAPS_DEFAULT_COUNT;
  if (!d.resolution) d.resolution = PB_IMAGE_MAPS_DEFAULT_RESOLUTION;
  if (!d.candidates) d.candidates = PB_IMAGE_MAPS_DEFAULT_CANDIDATES > d.count ? PB_IMAGE_MAPS_DEFAULT_CANDIDATES : d.count;
  if (!d.march_steps) d.march_steps = PB_IMAGE_MAPS_DEFAULT_MARCH;
  if (!d.secant_steps) d.secant_steps = PB_IMAGE_MAPS_DEFAULT_SECANT;
  if (d.epsilon == 0.0f) d.epsilon = PB_IMAGE_MAPS_EPSILON;
  if (!d.update_every) d.update_every = PB_IMAGE_MAPS_DEFAULT_UPDATE_EVERY;
  if (!d.seed) d.seed = 0x5eed003ull;
  if (d.count > PB_IMAGE_MAPS_MAX)
    return pb_fail(PB_ERR_USAGE, "image maps: %u maps (1..%u)", d.count, (unsigned)PB_IMAGE_MAPS_MAX);
  if (d.resolution < 8 || d.resolution > 1024)
    return pb_fail(PB_ERR_USAGE, "image maps: resolution %u (8..1024 texels per face side)", d.resolution);
  if (d.candidates < d.count || d.candidates > PB_IMAGE_MAPS_MAX_CANDIDATES)
    return pb_fail(PB_ERR_USAGE, "image maps: %u candidates for %u maps (%u..%u)", d.candidates, d.count, d.count,
                   (unsigned)PB_IMAGE_MAPS_MAX_CANDIDATES);
  if (d.march_steps > 4096 || d.secant_steps > 64 || !(d.epsilon > 0.0f) || !(d.epsilon < 1.0f))
    return pb_fail(PB_ERR_USAGE, "image maps: march %u, false position %u, epsilon %g out of range", d.march_steps,
                   d.secant_steps, d.epsilon);
  pb_image_maps *m = calloc(1, sizeof *m);
  if (!m) return pb_fail(PB_ERR_NOMEM, "image maps: out of memory");
  m->d = d;
  m->gs = gs;
  m->ncand = d.candidates;
  scene_box(m, s);
  pb_result r = PB_OK;
  m->host_cand = malloc((size_t)m->ncand * SELECT_PER * sizeof *m->host_cand);
  m->area = malloc((size_t)m->ncand * SELECT_PER * sizeof *m->area);
  m->seen = calloc((size_t)m->ncand * SELECT_PER, 1);
  if (!m->host_cand || !m->area || !m->seen) {
    r = pb_fail(PB_ERR_NOMEM, "image maps: out of memory");
    goto fail;
  }
  /* U: uniform points in the scene's box shrunk by 2 % per side (a point
   * on a wall sees half the scene), fixed by the seed. */
  uint64_t rs = d.seed;
  for (uint32_t i = 0; i < m->ncand; ++i)
    for (int c = 0; c < 3; ++c) {
      double u = (double)(splitmix(&rs) >> 11) * 0x1.0p-53;
      float lo = s->bounds_min[c], hi = s->bounds_max[c], e = 0.02f * (hi - lo);
      m->cand[i][c] = (float)(lo + e + u * (hi - lo - 2.0f * e));
    }
  pb_gpu_buffer_desc bd = {.name = "image_maps.maps",
                           .size = sizeof(pb_gpu_image_maps_info) + PB_IMAGE_MAPS_MAX * sizeof(pb_gpu_image_map)};
  if ((r = pb_gpu_buffer_create(g, &bd, &m->maps)) != PB_OK) goto fail;
  pb_gpu_buffer_desc td = {.name = "image_maps.texels",
                           .size = (uint64_t)d.count * 6u * d.resolution * d.resolution * sizeof(pb_gpu_image_texel)};
  if ((r = pb_gpu_buffer_create(g, &td, &m->texels)) != PB_OK) goto fail;
  pb_gpu_buffer_desc cd = {.name = "image_maps.candidates",
                           .size = sizeof(pb_gpu_image_maps_info) + m->ncand * sizeof(pb_gpu_image_map)};
  if ((r = pb_gpu_buffer_create(g, &cd, &m->cand_maps)) != PB_OK) goto fail;
  pb_gpu_buffer_desc ct = {.name = "image_maps.candidate_texels",
                           .size = (uint64_t)m->ncand * SELECT_PER * sizeof(pb_gpu_image_texel),
                           .readback = 1};
  if ((r = pb_gpu_buffer_create(g, &ct, &m->cand_texels)) != PB_OK) goto fail;
  static const pb_kernel_builds k = PB_KERNEL_BUILDS_GLTF(image_maps);
  pb_gpu_pipeline_desc pd = {.name = "pass.image_maps",
                             .binding_count = PB_IMAGE_BIND_COUNT,
                             .push_bytes = sizeof(pb_gpu_image_maps_push)};
  pb_kernel_select(&pd, &k, 0, gs->ray_query, PB_IMAGE_BIND_NODES);
  if ((r = pb_gpu_pipeline_create(g, &pd, &m->render_pipe)) != PB_OK) goto fail;
  pd.name = "pass.image_maps.select";
  if ((r = pb_gpu_pipeline_create(g, &pd, &m->select_pipe)) != PB_OK) goto fail;
  if ((r = bind_render(g, &m->render_pipe, gs, &m->maps, &m->texels)) != PB_OK) goto fail;
  if ((r = bind_render(g, &m->select_pipe, gs, &m->cand_maps, &m->cand_texels)) != PB_OK) goto fail;

  /* The initial selection: k greedy steps, then swap steps until C is
   * invariant (at most PB_IMAGE_MAPS_MAX_INITIAL_SWAPS). */
  double t0 = pb_time_now();
  if ((r = prepare_selection(g, m)) != PB_OK) goto fail;
  for (uint32_t i = 0; i < d.count; ++i) {
    uint32_t v = best_new(m);
    m->sel[m->nsel++] = v;
    account(m, v, +1);
  }
  for (uint32_t i = 0; i < PB_IMAGE_MAPS_MAX_INITIAL_SWAPS; ++i) {
    m->st.initial_swaps++;
    if (!swap_step(m)) break;
    m->st.swaps++;
  }
  coverage_stats(m);
  m->st.select_ms = (pb_time_now() - t0) * 1e3;
  pose_changed(m, s, NULL);
  if ((r = render_maps(g, m, 0, m->nsel)) != PB_OK) goto fail;
  pb_log_verbose("image maps: %u of %u candidates, %u^2 x 6 texels each; %.3g m^2 of the candidates' view "
                 "uncovered (%.3g covered); selection %.0f ms, maps %.0f ms",
                 m->nsel, m->ncand, d.resolution, m->st.uncovered_m2, m->st.coverage_m2, m->st.select_ms,
                 m->st.render_ms);
  *out = m;
  return PB_OK;
fail:
  pb_image_maps_destroy(g, m);
  return r;
}

/* The maps whose texel rays cross the box (image_maps_touch.comp): flags
 * per map slot. */
static pb_result touched_maps(pb_gpu *g, pb_image_maps *m, const float box[2][3], uint32_t flags[16]) {
  pb_result r;
  if (!m->touch_pipe.pipeline) {
    pb_gpu_buffer_desc bd = {.name = "image_maps.touch", .size = sizeof(pb_gpu_image_touch), .readback = 1};
    pb_gpu_pipeline_desc pd = {.name = "pass.image_maps.touch",
                               .spirv = pb_spv_image_maps_touch,
                               .spirv_bytes = sizeof pb_spv_image_maps_touch,
                               .binding_count = PB_IMAGE_BIND_COUNT,
                               .push_bytes = sizeof(pb_gpu_image_maps_push)};
    if ((r = pb_gpu_buffer_create(g, &bd, &m->touch)) != PB_OK ||
        (r = pb_gpu_pipeline_create(g, &pd, &m->touch_pipe)) != PB_OK)
      return r;
    const pb_gpu_buffer *b[PB_IMAGE_BIND_COUNT] = {
        [PB_IMAGE_BIND_NODES] = &m->maps,    [PB_IMAGE_BIND_TRIS] = &m->maps,
        [PB_IMAGE_BIND_INDICES] = &m->maps,  [PB_IMAGE_BIND_POSITIONS] = &m->maps,
        [PB_IMAGE_BIND_TRI_MATERIAL] = &m->maps, [PB_IMAGE_BIND_MAPS] = &m->maps,
        [PB_IMAGE_BIND_TEXELS] = &m->texels, [PB_IMAGE_BIND_RAYS] = &m->maps,
        [PB_IMAGE_BIND_HITS] = &m->maps,     [PB_IMAGE_BIND_COUNTS] = &m->touch};
    if ((r = pb_gpu_pipeline_bind(g, &m->touch_pipe, b, PB_IMAGE_BIND_COUNT)) != PB_OK) return r;
  }
  pb_gpu_image_touch t;
  memset(&t, 0, sizeof t);
  memcpy(t.box_min, box[0], sizeof t.box_min);
  memcpy(t.box_max, box[1], sizeof t.box_max);
  if ((r = pb_gpu_buffer_upload(g, &m->touch, 0, &t, sizeof t)) != PB_OK) return r;
  if ((r = render(g, &m->touch_pipe, 0, m->nsel, m->d.resolution)) != PB_OK) return r;
  if ((r = pb_gpu_buffer_download(g, &m->touch, 0, &t, sizeof t)) != PB_OK) return r;
  memcpy(flags, t.touched, sizeof t.touched);
  return PB_OK;
}

/* Section 4.1's progressive update, rendering only what changed.
 * The maps hold geometry alone (positions, normals, triangles,
 * materials), so:
 *   - a pose in which no vertex moved (a moving light or camera, a still
 *     frame of an animation) leaves every map valid and renders none; a
 *     swap step then runs on the candidates' maps already read back (still
 *     right) and only the swapped centre's map is rendered;
 *   - when vertices moved, only the maps with a texel ray crossing the box
 *     of the moved triangles (old and new positions: image_maps_touch.comp)
 *     are rendered again, exactly the maps in which a first surface can
 *     have changed; every update_every-th update the candidates see the new
 *     pose first and the swapped-in map is rendered too. */
pb_result pb_image_maps_update(pb_gpu *g, pb_image_maps *m, const pb_scene *s) {
  pb_result r;
  float box[2][3];
  int moved = pose_changed(m, s, box);
  uint32_t render_slot[PB_IMAGE_MAPS_MAX + 1];
  memset(render_slot, 0, sizeof render_slot);
  if (moved) {
    scene_box(m, s);
    uint32_t flags[16];
    if ((r = touched_maps(g, m, (const float(*)[3])box, flags)) != PB_OK) return r;
    for (uint32_t i = 0; i < m->nsel; ++i) render_slot[i] = flags[i] != 0;
  }
  if (++m->updates % m->d.update_every == 0) {
    double t0 = pb_time_now();
    if (moved && (r = prepare_selection(g, m)) != PB_OK) return r;
    uint32_t before[PB_IMAGE_MAPS_MAX + 1];
    memcpy(before, m->sel, sizeof before);
    if (swap_step(m)) m->st.swaps++;
    coverage_stats(m);
    m->st.select_ms = (pb_time_now() - t0) * 1e3;
    for (uint32_t i = 0; i < m->nsel; ++i)
      if (m->sel[i] != before[i]) render_slot[i] = 1;
  }
  uint32_t n = 0;
  for (uint32_t i = 0; i < m->nsel; ++i) n += render_slot[i];
  if (n == 0) {
    m->st.renders_skipped++;
    if (!moved) return PB_OK;
    /* Moved geometry no map sees: the maps stay, the scene's box (the
     * search's clip) follows the pose. */
    float c[PB_IMAGE_MAPS_MAX][3];
    for (uint32_t i = 0; i < m->nsel; ++i) memcpy(c[i], m->cand[m->sel[i]], sizeof c[i]);
    return upload_maps(g, &m->maps, m, (const float(*)[3])c, m->nsel, m->d.resolution);
  }
  if (n == m->nsel) return render_maps(g, m, 0, m->nsel);
  double t0 = pb_time_now();
  for (uint32_t i = 0; i < m->nsel; ++i)
    if (render_slot[i] && (r = render_maps(g, m, i, 1)) != PB_OK) return r;
  m->st.render_ms = (pb_time_now() - t0) * 1e3;
  return PB_OK;
}

void pb_image_maps_destroy(pb_gpu *g, pb_image_maps *m) {
  if (!m) return;
  pb_gpu_pipeline_destroy(g, &m->render_pipe);
  pb_gpu_pipeline_destroy(g, &m->select_pipe);
  pb_gpu_pipeline_destroy(g, &m->query_pipe);
  pb_gpu_pipeline_destroy(g, &m->touch_pipe);
  pb_gpu_buffer_destroy(g, &m->touch);
  pb_gpu_buffer_destroy(g, &m->maps);
  pb_gpu_buffer_destroy(g, &m->texels);
  pb_gpu_buffer_destroy(g, &m->cand_maps);
  pb_gpu_buffer_destroy(g, &m->cand_texels);
  pb_gpu_buffer_destroy(g, &m->rays);
  pb_gpu_buffer_destroy(g, &m->hits);
  pb_gpu_buffer_destroy(g, &m->counts);
  free(m->host_cand);
  free(m->area);
  free(m->seen);
  free(m->pose);
  free(m);
}

const pb_gpu_buffer *pb_image_maps_buffer(const pb_image_maps *m) { return &m->maps; }
const pb_gpu_buffer *pb_image_maps_texels(const pb_image_maps *m) { return &m->texels; }

void pb_image_maps_get_stats(const pb_image_maps *m, pb_image_maps_stats *out) {
  *out = m->st;
  out->count = m->nsel;
  out->resolution = m->d.resolution;
  out->candidates = m->ncand;
}

void pb_image_maps_centers(const pb_image_maps *m, float (*out)[3]) {
  for (uint32_t i = 0; i < m->nsel; ++i) memcpy(out[i], m->cand[m->sel[i]], sizeof out[i]);
}

pb_result pb_image_maps_query(pb_gpu *g, pb_image_maps *m, const pb_gpu_ray *rays, uint32_t n, pb_gpu_hit *hits,
                              pb_gpu_image_counts *counts, double *gpu_ms) {
  pb_result r;
  if (gpu_ms) *gpu_ms = -1.0;
  if (n == 0) return PB_OK;
  if (n > m->query_capacity) {
    pb_gpu_pipeline_destroy(g, &m->query_pipe);
  pb_gpu_pipeline_destroy(g, &m->touch_pipe);
  pb_gpu_buffer_destroy(g, &m->touch);
    pb_gpu_buffer_destroy(g, &m->rays);
    pb_gpu_buffer_destroy(g, &m->hits);
    pb_gpu_buffer_destroy(g, &m->counts);
    m->query_capacity = 0;
    pb_gpu_buffer_desc rd = {.name = "image_maps.rays", .size = (uint64_t)n * sizeof(pb_gpu_ray)};
    pb_gpu_buffer_desc hd = {.name = "image_maps.hits", .size = (uint64_t)n * sizeof(pb_gpu_hit), .readback = 1};
    pb_gpu_buffer_desc cd = {.name = "image_maps.counts", .size = sizeof(pb_gpu_image_counts), .readback = 1};
    pb_gpu_pipeline_desc pd = {.name = "image_maps.query",
                               .spirv = pb_spv_image_maps_query,
                               .spirv_bytes = sizeof pb_spv_image_maps_query,
                               .binding_count = PB_IMAGE_BIND_COUNT,
                               .push_bytes = sizeof(pb_gpu_image_maps_push)};
    if ((r = pb_gpu_buffer_create(g, &rd, &m->rays)) != PB_OK || (r = pb_gpu_buffer_create(g, &hd, &m->hits)) != PB_OK ||
        (r = pb_gpu_buffer_create(g, &cd, &m->counts)) != PB_OK ||
        (r = pb_gpu_pipeline_create(g, &pd, &m->query_pipe)) != PB_OK)
      return r;
    const pb_gpu_buffer *b[PB_IMAGE_BIND_COUNT] = {
        [PB_IMAGE_BIND_NODES] = &m->maps,    [PB_IMAGE_BIND_TRIS] = &m->maps,
        [PB_IMAGE_BIND_INDICES] = &m->maps,  [PB_IMAGE_BIND_POSITIONS] = &m->maps,
        [PB_IMAGE_BIND_TRI_MATERIAL] = &m->maps, [PB_IMAGE_BIND_MAPS] = &m->maps,
        [PB_IMAGE_BIND_TEXELS] = &m->texels, [PB_IMAGE_BIND_RAYS] = &m->rays,
        [PB_IMAGE_BIND_HITS] = &m->hits,     [PB_IMAGE_BIND_COUNTS] = &m->counts};
    if ((r = pb_gpu_pipeline_bind(g, &m->query_pipe, b, PB_IMAGE_BIND_COUNT)) != PB_OK) return r;
    m->query_capacity = n;
  }
  pb_gpu_image_counts zero;
  memset(&zero, 0, sizeof zero);
  if ((r = pb_gpu_buffer_upload(g, &m->rays, 0, rays, (uint64_t)n * sizeof *rays)) != PB_OK ||
      (r = pb_gpu_buffer_upload(g, &m->counts, 0, &zero, sizeof zero)) != PB_OK)
    return r;
  pb_gpu_image_maps_push push = {.ray_count = n};
  if ((r = pb_gpu_begin(g)) != PB_OK) return r;
  pb_gpu_timestamp(g, 0);
  r = pb_gpu_dispatch(g, &m->query_pipe, &push, n);
  pb_gpu_timestamp(g, 1);
  double t0 = pb_time_now();
  pb_result rs = pb_gpu_submit(g);
  double wall = (pb_time_now() - t0) * 1e3;
  if (r == PB_OK) r = rs;
  if (r != PB_OK) return r;
  if (gpu_ms) {
    double ms = pb_gpu_elapsed_ms(g, 0, 1);
    *gpu_ms = ms >= 0 ? ms : wall;
  }
  if ((r = pb_gpu_buffer_download(g, &m->hits, 0, hits, (uint64_t)n * sizeof *hits)) != PB_OK) return r;
  if (counts && (r = pb_gpu_buffer_download(g, &m->counts, 0, counts, sizeof *counts)) != PB_OK) return r;
  return PB_OK;
}
