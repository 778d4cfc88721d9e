/* The readback (readback.h): the only place pixels come to the host. */
#include "render/frame/readback.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "shared/pb_filter.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_resolve.h"

/* The `bytes` of b from `offset` on the host: its mapping when cached,
 * else a staged copy into *scratch (grown as needed, freed by the caller).
 * *view is set on every path (NULL when the copy cannot be made), so a
 * caller never reads an unset pointer. */
static pb_result host_view_at(pb_gpu *g, const pb_gpu_buffer *b, uint64_t offset, uint64_t bytes, void **scratch,
                              const void **view) {
  *view = NULL;
  if (b->mapped && b->cached) {
    *view = (const char *)b->mapped + offset;
    pb_gpu_note_read_back(g, bytes);
    return PB_OK;
  }
  void *p = malloc(bytes ? bytes : 1);
  if (!p) return pb_fail(PB_ERR_NOMEM, "render: out of memory reading back %llu bytes", (unsigned long long)bytes);
  *scratch = p;
  *view = p;
  return pb_gpu_buffer_read_back(g, b, offset, p, bytes);
}

/* The first `bytes` of b (host_view_at from 0). */
static pb_result host_view(pb_gpu *g, const pb_gpu_buffer *b, uint64_t bytes, void **scratch, const void **view) {
  return host_view_at(g, b, 0, bytes, scratch, view);
}

/* The former host resolve (frame.c and shading_correction.c before the
 * resolve pass), kept as the reference the pass is tested against
 * (PB_RESOLVE_ON_HOST=1, tests/frame_same_pixels.py): the same planes,
 * computed here from the accumulators. */
static pb_result host_resolve(pb_gpu *g, const pb_frame_targets *t, uint32_t pixels, float inv, int opaque,
                              float *pl) {
  pb_gpu_accum *a = malloc((size_t)pixels * sizeof *a);
  pb_gpu_photon_accum *pa = t->photons ? malloc((size_t)pixels * sizeof *pa) : NULL;
  pb_gpu_photon_nmap *pn = t->nmap ? malloc((size_t)pixels * sizeof *pn) : NULL;
  pb_result r = PB_OK;
  if (!a || (t->photons && !pa) || (t->nmap && !pn)) r = pb_fail(PB_ERR_NOMEM, "render: out of memory");
  if (r == PB_OK) r = pb_gpu_buffer_download(g, &t->accum, 0, a, (uint64_t)pixels * sizeof *a);
  if (r == PB_OK && pa) r = pb_gpu_buffer_download(g, &t->paccum, 0, pa, (uint64_t)pixels * sizeof *pa);
  if (r == PB_OK && pn) r = pb_gpu_buffer_download(g, &t->pnmap, 0, pn, (uint64_t)pixels * sizeof *pn);
  for (uint32_t i = 0; r == PB_OK && i < pixels; ++i) {
#define P(plane, ch, c) pl[(size_t)(plane) * pixels + (size_t)i * (ch) + (c)]
#define G(v) (isfinite(v) ? (v) : 0.0f)
    for (int k = 0; k < 4; ++k) P(PB_RESOLVE_BEAUTY, 4, k) = a[i].beauty[k] * inv;
    if (opaque) P(PB_RESOLVE_BEAUTY, 4, 3) = 1.0f;
    for (int k = 0; k < 4; ++k) P(PB_RESOLVE_BEAUTY, 4, k) = G(P(PB_RESOLVE_BEAUTY, 4, k));
    float nl = sqrtf(a[i].normal[0] * a[i].normal[0] + a[i].normal[1] * a[i].normal[1] + a[i].normal[2] * a[i].normal[2]);
    for (int k = 0; k < 3; ++k) {
      float d = a[i].direct[k] * inv, al = a[i].albedo[k] * inv, e = a[i].emission[k] * inv;
      float nk = nl > 0 ? a[i].normal[k] / nl : 0.0f;
      P(PB_RESOLVE_DIRECT, 3, k) = G(d);
      P(PB_RESOLVE_ALBEDO, 3, k) = G(al);
      P(PB_RESOLVE_EMISSION, 3, k) = G(e);
      P(PB_RESOLVE_NORMAL, 3, k) = G(nk);
    }
    float z = a[i].beauty[3] > 0 ? a[i].depth / a[i].beauty[3] : 0.0f;
    P(PB_RESOLVE_DEPTH, 1, 0) = G(z);
    P(PB_RESOLVE_MATERIAL, 1, 0) = G(a[i].material);
    if (pa) {
      for (int k = 0; k < 3; ++k) {
        float ind = pa[i].indirect[k] * inv, c = pa[i].caustic[k] * inv;
        P(PB_RESOLVE_INDIRECT, 3, k) = G(ind);
        P(PB_RESOLVE_CAUSTIC, 3, k) = G(c);
      }
      P(PB_RESOLVE_KPD, 2, 0) = pa[i].indirect[3];
      P(PB_RESOLVE_KPD, 2, 1) = a[i].beauty[3];
    }
    if (pn) {
      const float *src[3] = {pn[i].geo, pn[i].dir, pn[i].ns};
      const uint32_t plane[3] = {PB_RESOLVE_GEO_NORMAL, PB_RESOLVE_PHOTON_DIR, PB_RESOLVE_SHADING_NORMAL};
      const uint32_t ch[3] = {3, 3, 4};
      for (int v = 0; v < 3; ++v) {
        float l = sqrtf(src[v][0] * src[v][0] + src[v][1] * src[v][1] + src[v][2] * src[v][2]);
        for (int k = 0; k < 3; ++k) P(plane[v], ch[v], k) = l > 0.0f && isfinite(l) ? src[v][k] / l : 0.0f;
      }
      float frac = pn[i].ns[3] * inv;
      P(PB_RESOLVE_SHADING_NORMAL, 4, 3) = isfinite(frac) ? fminf(fmaxf(frac, 0.0f), 1.0f) : 0.0f;
    }
#undef G
#undef P
  }
  free(a);
  free(pa);
  free(pn);
  return r;
}

/* The band's planes from `planes` and `pplanes` (the targets' or a ring
 * slot's) into out. */
static pb_result read_band(pb_gpu *g, const pb_frame_targets *t, const pb_gpu_buffer *planes,
                           const pb_gpu_buffer *pplanes, int host, int mode, uint32_t pixels, size_t pixel_base,
                           size_t n, float inv_spp, int opaque, int nmap_aovs, pb_render_result *out, double *k_sum,
                           double *hit_sum) {
  /* base[0]: planes 0 .. PB_RESOLVE_BASE_CHANNELS - 1, base[1]: the photon
   * planes from PB_RESOLVE_BASE_CHANNELS on (two buffers, shared/pb_resolve.h). */
  void *scratch = NULL, *scratch2 = NULL;
  const void *view = NULL, *view2 = NULL;
  pb_result r;
  if (!host && mode != PB_RENDER_READBACK_ALL) {
    /* A lean readback (render.h pb_render_desc.readback): the beauty plane
     * alone (serve) or none; k_PD's sums come from the resolve's reduction
     * (pb_readback_kpd), not the plane; the rest stays on the GPU
     * (out->gpu). */
    r = PB_OK;
    if (mode == PB_RENDER_READBACK_BEAUTY && out->beauty) {
      r = host_view_at(g, planes, (uint64_t)PB_RESOLVE_BEAUTY * pixels * sizeof(float),
                       (uint64_t)pixels * 4 * sizeof(float), &scratch, &view);
      if (r == PB_OK) memcpy(out->beauty + pixel_base * 4, view, (size_t)pixels * 4 * sizeof(float));
    }
    free(scratch);
    return r;
  }
  if (host) {
    if (!(scratch = malloc((uint64_t)pixels * t->channels * sizeof(float))))
      return pb_fail(PB_ERR_NOMEM, "render: out of memory");
    view = scratch;
    view2 = (const float *)scratch + (size_t)PB_RESOLVE_BASE_CHANNELS * pixels;
    r = host_resolve(g, t, pixels, inv_spp, opaque, scratch);
  } else {
    r = host_view(g, planes, (uint64_t)pixels * PB_RESOLVE_BASE_CHANNELS * sizeof(float), &scratch, &view);
    if (r == PB_OK && t->photons)
      r = host_view(g, pplanes, (uint64_t)pixels * (t->channels - PB_RESOLVE_BASE_CHANNELS) * sizeof(float),
                    &scratch2, &view2);
  }
  if (r != PB_OK) {
    free(scratch);
    free(scratch2);
    return r;
  }
  const float *base[2] = {view, view2};
#define PLANE(p) \
  ((uint32_t)(p) < (uint32_t)PB_RESOLVE_BASE_CHANNELS ? base[0] + (size_t)(p) * pixels                      \
                                                   : base[1] + ((size_t)(p) - PB_RESOLVE_BASE_CHANNELS) * pixels)
  struct { float *dst; uint32_t plane, ch; } aov[] = {
      {out->beauty, PB_RESOLVE_BEAUTY, 4},     {out->direct, PB_RESOLVE_DIRECT, 3},
      {out->albedo, PB_RESOLVE_ALBEDO, 3},     {out->normal, PB_RESOLVE_NORMAL, 3},
      {out->depth, PB_RESOLVE_DEPTH, 1},       {out->material, PB_RESOLVE_MATERIAL, 1},
      {out->emission, PB_RESOLVE_EMISSION, 3}, {t->photons ? out->indirect : NULL, PB_RESOLVE_INDIRECT, 3},
      {t->photons ? out->caustic : NULL, PB_RESOLVE_CAUSTIC, 3}};
  for (size_t a = 0; a < sizeof aov / sizeof *aov; ++a)
    if (aov[a].dst)
      memcpy(aov[a].dst + pixel_base * aov[a].ch, PLANE(aov[a].plane),
             (size_t)pixels * aov[a].ch * sizeof(float));
  if (t->photons) {
    const float *kp = PLANE(PB_RESOLVE_KPD);
    for (uint32_t i = 0; i < pixels; ++i) *k_sum += kp[2 * i], *hit_sum += kp[2 * i + 1];
  }
  if (t->nmap && nmap_aovs) {
    if (!out->geo_normal) {
      out->geo_normal = calloc(3 * n, sizeof(float));
      out->photon_dir = calloc(3 * n, sizeof(float));
      out->shading_normal = calloc(4 * n, sizeof(float));
      if (!out->geo_normal || !out->photon_dir || !out->shading_normal) {
        free(scratch);
        free(scratch2);
        return pb_fail(PB_ERR_NOMEM, "render: out of memory for the shading-correction AOVs");
      }
    }
    memcpy(out->geo_normal + 3 * pixel_base, PLANE(PB_RESOLVE_GEO_NORMAL), (size_t)pixels * 3 * sizeof(float));
    memcpy(out->photon_dir + 3 * pixel_base, PLANE(PB_RESOLVE_PHOTON_DIR), (size_t)pixels * 3 * sizeof(float));
    memcpy(out->shading_normal + 4 * pixel_base, PLANE(PB_RESOLVE_SHADING_NORMAL), (size_t)pixels * 4 * sizeof(float));
  }
#undef PLANE
  free(scratch);
  free(scratch2);
  return PB_OK;
}

pb_result pb_readback_band(pb_gpu *g, const pb_frame_targets *t, int mode, uint32_t pixels, size_t pixel_base,
                           size_t n, float inv_spp, int opaque, int nmap_aovs, pb_render_result *out, double *k_sum,
                           double *hit_sum) {
  const char *env = getenv("PB_RESOLVE_ON_HOST");
  return read_band(g, t, &t->planes, &t->pplanes, env && env[0] == '1', mode, pixels, pixel_base, n, inv_spp,
                   opaque, nmap_aovs, out, k_sum, hit_sum);
}

pb_result pb_readback_planes(pb_gpu *g, const pb_render_gpu_planes *p, pb_render_result *out) {
  pb_frame_targets t;
  memset(&t, 0, sizeof t);
  t.photons = p->photons, t.nmap = p->nmap, t.channels = p->channels;
  double k = 0, h = 0; /* the frame's k_PD is in its statistics already */
  return read_band(g, &t, p->planes, p->pplanes, 0, PB_RENDER_READBACK_ALL, p->pixels, 0, p->pixels, 1.0f, 0,
                   p->nmap_aovs, out, &k, &h);
}

/* The planes of shared/pb_resolve.h: offset (floats per pixel) and channels. */
static const struct { uint32_t plane, ch; } k_planes[] = {
    {PB_RESOLVE_BEAUTY, 4},   {PB_RESOLVE_DIRECT, 3},      {PB_RESOLVE_ALBEDO, 3},     {PB_RESOLVE_NORMAL, 3},
    {PB_RESOLVE_DEPTH, 1},    {PB_RESOLVE_MATERIAL, 1},    {PB_RESOLVE_EMISSION, 3},   {PB_RESOLVE_INDIRECT, 3},
    {PB_RESOLVE_CAUSTIC, 3},  {PB_RESOLVE_KPD, 2},         {PB_RESOLVE_GEO_NORMAL, 3}, {PB_RESOLVE_PHOTON_DIR, 3},
    {PB_RESOLVE_SHADING_NORMAL, 4}};

uint64_t pb_readback_ring_planes(int mode, uint64_t keep) {
  if (mode == PB_RENDER_READBACK_ALL) return PB_RENDER_KEEP_ALL;
  return (mode == PB_RENDER_READBACK_BEAUTY ? PB_RENDER_KEEP(PB_RESOLVE_BEAUTY) : 0) | keep;
}

uint64_t pb_readback_ring_record(pb_gpu *g, const pb_frame_targets *t, uint32_t slot, uint32_t pixels, int mode,
                                 uint64_t keep, uint64_t *bytes) {
  uint64_t want = pb_readback_ring_planes(mode, keep);
  *bytes = 0;
  if (want == PB_RENDER_KEEP_ALL) { /* every plane, as two copies */
    pb_gpu_copy(g, &t->planes, 0, &t->ring[slot][0], 0, (uint64_t)pixels * PB_RESOLVE_BASE_CHANNELS * sizeof(float));
    *bytes = (uint64_t)pixels * t->channels * sizeof(float);
    if (t->photons)
      pb_gpu_copy(g, &t->pplanes, 0, &t->ring[slot][1], 0,
                  (uint64_t)pixels * (t->channels - PB_RESOLVE_BASE_CHANNELS) * sizeof(float));
    return want;
  }
  /* A lean readback: the planes it reads (the beauty or none) and those the
   * caller keeps, each where it lies in the planes. */
  uint64_t got = 0;
  for (size_t k = 0; k < sizeof k_planes / sizeof *k_planes; ++k) {
    uint32_t p = k_planes[k].plane;
    if (!(want & PB_RENDER_KEEP(p)) || p >= t->channels) continue;
    int second = p >= PB_RESOLVE_BASE_CHANNELS;
    uint64_t off = (uint64_t)(second ? p - PB_RESOLVE_BASE_CHANNELS : p) * pixels * sizeof(float);
    pb_gpu_copy(g, second ? &t->pplanes : &t->planes, off, &t->ring[slot][second], off,
                (uint64_t)pixels * k_planes[k].ch * sizeof(float));
    *bytes += (uint64_t)pixels * k_planes[k].ch * sizeof(float);
    got |= PB_RENDER_KEEP(p);
  }
  return got;
}

pb_result pb_readback_kpd(pb_gpu *g, const pb_frame_targets *t, double *k_sum, double *hit_sum) {
  pb_gpu_resolve_kpd s;
  pb_result r = pb_gpu_buffer_read_back(g, &t->kpd, 0, &s, sizeof s);
  if (r != PB_OK) return r;
  /* 64-bit fixed point (shared/pb_resolve.h): exact in a double below 2^53. */
  double scale = 1.0 / (double)(1u << PB_RESOLVE_KPD_FRAC_BITS);
  *k_sum = ((double)s.photons_hi * 4294967296.0 + (double)s.photons_lo) * scale;
  *hit_sum = ((double)s.hits_hi * 4294967296.0 + (double)s.hits_lo) * scale;
  return PB_OK;
}

pb_result pb_readback_ring(pb_gpu *g, const pb_frame_targets *t, int mode, uint32_t slot, uint32_t pixels,
                           int nmap_aovs, pb_render_result *out, double *k_sum, double *hit_sum) {
  /* inv_spp and opaque only serve the host resolve, which is not used here. */
  return read_band(g, t, &t->ring[slot][0], &t->ring[slot][1], 0, mode, pixels, 0, pixels, 1.0f, 0, nmap_aovs, out,
                   k_sum, hit_sum);
}

pb_result pb_readback_guard(pb_gpu *g, const pb_frame_targets *t, uint64_t *count) {
  uint32_t c = 0;
  pb_result r = pb_gpu_buffer_read_back(g, &t->guard, 0, &c, sizeof c);
  *count = c;
  return r;
}

pb_result pb_readback_preview(pb_gpu *g, const pb_frame_targets *t, size_t n, uint32_t samples, float *beauty) {
  void *scratch = NULL;
  const void *view; /* host_view sets it on every path */
  pb_result r = host_view(g, &t->accum, (uint64_t)n * sizeof(pb_gpu_accum), &scratch, &view);
  if (r == PB_OK) {
    const pb_gpu_accum *a = view;
    float inv = 1.0f / (float)samples;
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < 4; ++k) {
        float v = a[i].beauty[k] * inv;
        beauty[4 * i + k] = isfinite(v) ? v : 0.0f;
      }
  }
  free(scratch);
  return r;
}

pb_result pb_readback_temporal_stats(pb_gpu *g, const pb_gpu_buffer *b, pb_temporal_stats *stats) {
  pb_gpu_temporal_stats s;
  pb_result r = pb_gpu_buffer_read_back(g, b, 0, &s, sizeof s);
  if (r == PB_OK) pb_temporal_stats_of(&s, stats);
  return r;
}
