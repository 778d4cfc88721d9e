/* One frame's plan; see plan.h. */
#include "render/frame/plan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/photon/photon.h"
#include "render/frame/targets.h"
#include "scene/camera.h"

/* ---- one frame's plan ------------------------------------------------------ */

static pb_result validate(const pb_scene *s, int camera, uint32_t w, uint32_t h, const pb_render_desc *d) {
  if (camera < 0 || (uint32_t)camera >= s->camera_count)
    return pb_fail(PB_ERR_USAGE, "render: camera %d of %u", camera, s->camera_count);
  if (w == 0 || h == 0 || w > 16384 || h > 16384)
    return pb_fail(PB_ERR_USAGE, "render: image size %ux%u (1..16384 per side)", w, h);
  if (d->spp > (1u << 20)) return pb_fail(PB_ERR_USAGE, "render: %u samples per pixel (at most 2^20)", d->spp);
  if (d->alpha < 0.0f || !(d->alpha < 1.0f))
    return pb_fail(PB_ERR_USAGE, "render: progressive alpha %g (in (0, 1))", d->alpha);
  if (!(d->glossy_path_roughness <= 1.0f))
    return pb_fail(PB_ERR_USAGE, "render: glossy path roughness %g (at most 1)", d->glossy_path_roughness);
  if (d->full_width && ((uint64_t)d->crop_x + w > d->full_width || (uint64_t)d->crop_y + h > d->full_height ||
                        d->full_width > 65536 || d->full_height > 65536))
    return pb_fail(PB_ERR_USAGE, "render: crop %ux%u at (%u, %u) does not fit in the %ux%u frame", w, h, d->crop_x,
                   d->crop_y, d->full_width, d->full_height);
  if (!(d->time_limit_s >= 0) || !isfinite(d->time_limit_s))
    return pb_fail(PB_ERR_USAGE, "render: time limit %g s is not a duration", d->time_limit_s);
  if (!(d->noise_threshold >= 0 && d->noise_threshold < 1))
    return pb_fail(PB_ERR_USAGE, "render: noise threshold %g is not in [0, 1) (RMS noise of the display image)",
                   d->noise_threshold);
  if (d->max_specular_depth > PB_RENDER_MAX_SPECULAR_DEPTH)
    return pb_fail(PB_ERR_USAGE, "render: --max-specular-depth %u (at most %d)", d->max_specular_depth,
                   PB_RENDER_MAX_SPECULAR_DEPTH);
  return PB_OK;
}

/* Band: whole rows whose per-pixel targets each fit one storage buffer (the
 * largest: the accumulators, 80 bytes per pixel; targets.h). Never
 * truncated: a row that does not fit is refused. */
static pb_result bands_of(pb_gpu *g, uint32_t width, uint32_t height, pb_frame_plan *p) {
  const pb_gpu_limits *lim = pb_gpu_get_limits(g);
  uint64_t per_pixel = pb_frame_targets_max_pixel_bytes();
  uint64_t max_pixels = lim->max_storage_buffer_range / per_pixel;
  if (max_pixels > lim->max_allocation / per_pixel) max_pixels = lim->max_allocation / per_pixel;
  if (max_pixels < width)
    return pb_fail(PB_ERR_LIMIT, "render: one row of %u pixels needs %llu bytes of G-buffer, over the device's "
                   "storage-buffer limit of %llu bytes; render a narrower image",
                   width, (unsigned long long)(width * per_pixel),
                   (unsigned long long)lim->max_storage_buffer_range);
  p->band_rows = (uint32_t)(max_pixels / width);
  if (p->band_rows > height) p->band_rows = height;
  p->shape.band_pixels = p->band_rows * width;
  p->bands = (height + p->band_rows - 1) / p->band_rows;
  return PB_OK;
}

/* The shape's tracer: the settings' photon tracing with its defaults. Set
 * field by field into the zeroed shape (pb_image_maps_desc has padding). */
static void tracer_shape(const pb_render_desc *d, pb_tracer_desc *t) {
  t->kind = d->tracer;
  t->photon.photons = d->photons;
  t->photon.max_bounces = d->photon_bounces;
  t->photon.smoothing = d->smoothing > 0.0f ? d->smoothing : PB_PHOTON_SMOOTHING_DEFAULT;
  t->photon.r_max = d->r_max;
  t->photon.smoothing_caustic = d->smoothing_caustic;
  t->photon.first_bounce = d->first_bounce;
  t->photon.bandwidth_c0 = d->bandwidth_c0;
  t->photon.caustic_share = d->caustic_share;
  t->images.count = d->image_maps;
  t->images.resolution = d->image_map_resolution;
}

/* The frame's constants but the band's pixels (pixel_base, pixel_count). */
static void frame_constants(const pb_scene *s, const pb_gpu_scene *gs, int camera, uint32_t width, uint32_t height,
                            const pb_render_desc *d, uint32_t spp, pb_gpu_frame *fr) {
  memset(fr, 0, sizeof *fr);
  const pb_camera *cam = &s->cameras[camera];
  if (d->full_width) {
    pb_camera_view(cam, d->full_width, d->full_height, &fr->cam);
    fr->key_x0 = d->crop_x, fr->key_y0 = d->crop_y, fr->key_width = d->full_width;
  } else {
    pb_camera_view(cam, width, height, &fr->cam);
  }
  fr->width = width;
  fr->height = height;
  fr->spp = spp;
  fr->light_count = gs->light_count;
  fr->emitter_count = (gs->features & PB_FEATURE_EMISSIVE) ? gs->emitter_count : 0;
  /* RR from 8: gbuffer.comp */
  fr->max_specular_depth = d->max_specular_depth ? d->max_specular_depth : PB_RENDER_MAX_SPECULAR_DEPTH;
  fr->seed_lo = (uint32_t)d->seed;
  fr->seed_hi = (uint32_t)(d->seed >> 32);
  fr->flags = (d->direct_only ? PB_GPU_FRAME_DIRECT_ONLY : 0u) | (d->jitter ? PB_GPU_FRAME_JITTER : 0u) |
              (d->time_limit_s > 0 || d->noise_threshold > 0 ? PB_GPU_FRAME_OPEN_SAMPLES : 0u);
  float gr = d->glossy_path_roughness == 0.0f ? PB_RENDER_GLOSSY_PATH_ROUGHNESS : fmaxf(d->glossy_path_roughness, 0.0f);
  fr->glossy_path_alpha2 = gr * gr * gr * gr; /* alpha = roughness^2 */
  fr->tangent_base = gs->tangent_base;
  fr->uv1_base = gs->uv1_base;
  fr->color_base = gs->color_base;
  fr->principled2_base = gs->principled2_base;
}

/* Where the resolve's planes go after it: the filters and eq. 20 on the
 * GPU, the readback, frames in flight. */
static void decisions(const pb_scene *s, const pb_render_desc *d, const pb_render_io *io, pb_frame_plan *p) {
  const char *host_env = getenv("PB_RESOLVE_ON_HOST");
  p->host_resolve = host_env && host_env[0] == '1';
  int one_band = p->bands == 1, ctx = io->context != NULL;
  /* A lean readback (render.h pb_render_desc.readback): where nothing on
   * the host needs the AOVs. The GPU path in one band (the host path's
   * filters and eq. 20 work on the read-back arrays), a context to keep
   * the planes in, and a still run's means on the GPU when there is one
   * (else the caller averages the arrays). Everything else reads all. */
  p->readback = PB_RENDER_READBACK_ALL;
  if ((d->readback == PB_RENDER_READBACK_BEAUTY || d->readback == PB_RENDER_READBACK_STATS) && ctx && one_band &&
      !p->host_resolve && (!io->still_sum || io->still_sum->pixels == p->shape.band_pixels))
    p->readback = d->readback;
  p->nmap = p->photons && p->shape.scene.normal_maps;
  /* The shading-correction AOVs leave the GPU where eq. 20 can use them. */
  p->nmap_aovs = p->nmap && (s->features & PB_FEATURE_NORMAL_MAPS) && s->tangents && s->uvs;
  /* The filters of the indirect light: the sequence's chain, or one made
   * for this call's A-Trous (filters.h). */
  p->own_chain = !io->filters && p->photons && d->atrous_iterations;
  /* After the resolve, on the GPU: the filter chain and eq. 20, for an image
   * in one band (the filters read neighbours). Several bands, and the host
   * resolve of the tests (PB_RESOLVE_ON_HOST=1, readback.h), filter the
   * read-back AOVs on the host instead: the former path, the reference. */
  p->post_gpu = p->photons && one_band && !p->host_resolve;
  p->chain_gpu = p->post_gpu && (io->filters || p->own_chain);
  p->sc_on = !d->no_shading_correction && p->nmap_aovs;
  /* A still run's means on the GPU: after eq. 20, on the final planes of a
   * frame in one band (the host resolve of the tests: on the host). */
  p->still_gpu = io->still_sum && one_band && !p->host_resolve && io->still_sum->pixels == p->shape.band_pixels;
  /* Frames in flight (render.h): one band on the GPU path, with a context
   * to keep the tail in. The last submission then also copies the planes
   * into the readback ring and is not waited for. */
  p->defer = d->in_flight && ctx && one_band && p->post_gpu && !p->own_chain;
}

pb_result pb_frame_plan_of(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, int camera, uint32_t width,
                           uint32_t height, const pb_render_desc *d, const pb_render_io *io, pb_frame_plan *p) {
  memset(p, 0, sizeof *p);
  pb_result r = validate(s, camera, width, height, d);
  if (r != PB_OK) return r;
  p->photons = !d->direct_only && (io->photon_map || gs->light_count > 0 || s->world.present || gs->emitter_count > 0);
  p->spp = d->spp ? d->spp : 1;
  p->iters = p->photons ? (d->iterations ? d->iterations : 1) : 1;
  if (p->photons && p->spp < p->iters) p->spp = p->iters;
  p->pixels = (size_t)width * height;
  pb_frame_shape *sh = &p->shape;
  if ((r = bands_of(g, width, height, p)) != PB_OK) return r;
  sh->gs = gs;
  sh->photon_map = io->photon_map;
  sh->width = width, sh->height = height;
  sh->photons = p->photons;
  pb_render_plan_of(s, d->direct_only, &sh->scene);
  if (p->photons) {
    if (!io->photon_map) tracer_shape(d, &sh->tracer);
    sh->estimator = d->estimator;
    sh->upsample_levels = d->upsample_levels;
  }
  decisions(s, d, io, p);
  frame_constants(s, gs, camera, width, height, d, p->spp, &p->frame);
  return PB_OK;
}
