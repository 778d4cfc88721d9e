/* Per-pixel targets (targets.h). */
#include "render/frame/targets.h"

#include <string.h>

#include "shared/pb_gpu.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_resolve.h"

uint64_t pb_frame_targets_max_pixel_bytes(void) {
  uint64_t b = sizeof(pb_gpu_gbuffer);
  if (b < sizeof(pb_gpu_accum)) b = sizeof(pb_gpu_accum);
  if (b < sizeof(pb_gpu_photon_accum)) b = sizeof(pb_gpu_photon_accum);
  if (b < sizeof(pb_gpu_photon_nmap)) b = sizeof(pb_gpu_photon_nmap);
  if (b < PB_RESOLVE_BASE_CHANNELS * sizeof(float)) b = PB_RESOLVE_BASE_CHANNELS * sizeof(float);
  if (b < (PB_RESOLVE_NMAP_CHANNELS - PB_RESOLVE_BASE_CHANNELS) * sizeof(float))
    b = (PB_RESOLVE_NMAP_CHANNELS - PB_RESOLVE_BASE_CHANNELS) * sizeof(float);
  return b;
}

void pb_frame_targets_destroy(pb_gpu *g, pb_frame_targets *t) {
  if (!t) return;
  pb_gpu_buffer_destroy(g, &t->frame);
  pb_gpu_buffer_destroy(g, &t->gbuf);
  pb_gpu_buffer_destroy(g, &t->accum);
  pb_gpu_buffer_destroy(g, &t->paccum);
  pb_gpu_buffer_destroy(g, &t->pnmap);
  pb_gpu_buffer_destroy(g, &t->planes);
  pb_gpu_buffer_destroy(g, &t->pplanes);
  pb_gpu_buffer_destroy(g, &t->guard);
  pb_gpu_buffer_destroy(g, &t->kpd);
  for (int i = 0; i < PB_READBACK_RING; ++i)
    for (int k = 0; k < 2; ++k) pb_gpu_buffer_destroy(g, &t->ring[i][k]);
  memset(t, 0, sizeof *t);
}

pb_result pb_frame_targets_ring(pb_gpu *g, pb_frame_targets *t) {
  if (t->ring_made) return PB_OK;
  static const char *const names[PB_READBACK_RING][2] = {{"frame.ring0.resolved", "frame.ring0.resolved_photons"},
                                                         {"frame.ring1.resolved", "frame.ring1.resolved_photons"}};
  for (int i = 0; i < PB_READBACK_RING; ++i)
    for (int k = 0; k < 2; ++k) {
      const pb_gpu_buffer *src = k ? &t->pplanes : &t->planes;
      if (!src->buffer) continue;
      pb_gpu_buffer_desc d = {.name = names[i][k], .size = src->size, .host_visible = 1, .readback = 1};
      pb_result r = pb_gpu_buffer_create(g, &d, &t->ring[i][k]);
      if (r != PB_OK) return r; /* the caller destroys the targets */
    }
  t->ring_made = 1;
  return PB_OK;
}

pb_result pb_frame_targets_create(pb_gpu *g, uint32_t band_pixels, int photons, int nmap, pb_frame_targets *t) {
  memset(t, 0, sizeof *t);
  t->band_pixels = band_pixels;
  t->photons = photons;
  t->nmap = photons && nmap;
  t->channels = t->nmap ? PB_RESOLVE_NMAP_CHANNELS : photons ? PB_RESOLVE_PHOTON_CHANNELS : PB_RESOLVE_BASE_CHANNELS;
  uint64_t px = band_pixels;
  pb_gpu_buffer_desc fd = {.name = "frame.constants", .size = sizeof(pb_gpu_frame)};
  pb_gpu_buffer_desc gd = {.name = "frame.gbuffer", .size = px * sizeof(pb_gpu_gbuffer)};
  pb_gpu_buffer_desc ad = {.name = "frame.accum", .size = px * sizeof(pb_gpu_accum), .host_visible = 1};
  pb_gpu_buffer_desc od = {.name = "frame.resolved", .size = px * PB_RESOLVE_BASE_CHANNELS * sizeof(float),
                           .host_visible = 1, .readback = 1};
  pb_gpu_buffer_desc gu = {.name = "frame.guard", .size = 16, .host_visible = 1, .readback = 1};
  pb_gpu_buffer_desc kd = {.name = "frame.kpd_sums", .size = sizeof(pb_gpu_resolve_kpd), .host_visible = 1,
                           .readback = 1};
  pb_result r;
  if ((r = pb_gpu_buffer_create(g, &fd, &t->frame)) != PB_OK || (r = pb_gpu_buffer_create(g, &gd, &t->gbuf)) != PB_OK ||
      (r = pb_gpu_buffer_create(g, &ad, &t->accum)) != PB_OK || (r = pb_gpu_buffer_create(g, &od, &t->planes)) != PB_OK ||
      (r = pb_gpu_buffer_create(g, &gu, &t->guard)) != PB_OK || (r = pb_gpu_buffer_create(g, &kd, &t->kpd)) != PB_OK)
    goto fail;
  if (photons) {
    pb_gpu_buffer_desc pd = {.name = "frame.photon_accum", .size = px * sizeof(pb_gpu_photon_accum), .host_visible = 1};
    if ((r = pb_gpu_buffer_create(g, &pd, &t->paccum)) != PB_OK) goto fail;
    pb_gpu_buffer_desc qd = {.name = "frame.resolved_photons",
                             .size = px * (t->channels - PB_RESOLVE_BASE_CHANNELS) * sizeof(float), .host_visible = 1,
                             .readback = 1};
    if ((r = pb_gpu_buffer_create(g, &qd, &t->pplanes)) != PB_OK) goto fail;
    if (t->nmap) { /* the gather's eq. 20 sums (its SC_NORMAL_MAPS) */
      pb_gpu_buffer_desc nd = {.name = "frame.photon_nmap", .size = px * sizeof(pb_gpu_photon_nmap), .host_visible = 1};
      if ((r = pb_gpu_buffer_create(g, &nd, &t->pnmap)) != PB_OK) goto fail;
    }
  }
  return PB_OK;
fail:
  pb_frame_targets_destroy(g, t);
  return r;
}
