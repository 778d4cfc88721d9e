/* One frame's plan: its settings validated and every decision made once
 * (below), with the scene's plan (render/scene/scene_plan.h) in its shape. */
#ifndef PB_RENDER_PLAN_H
#define PB_RENDER_PLAN_H

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/estimate/estimator_desc.h"
#include "render/render.h"
#include "render/photon/tracer.h"
#include "render/scene/scene_plan.h"
#include "scene/scene.h"
#include "shared/pb_gpu.h"

/* ---- one frame's plan (frame.c) --------------------------------------------
 *
 * pb_frame_plan_of validates a frame's settings (pb_render_desc, with the
 * I/O objects it is given: pb_render_io) and
 * resolves, once, every default and every decision the frame makes before
 * it creates anything: the samples and photon maps, the bands, where the
 * resolve and the filters run (the one read of PB_RESOLVE_ON_HOST), what
 * the readback brings, whether the frame stays in flight, the frame's
 * constants, and the shape of its GPU resources. */

/* What shapes a frame's GPU resources (render.h pb_frame_context): the very
 * arguments they are created from (frame.c context_build reads nothing
 * else), so a context is reused only by a frame that would have created the
 * same ones. Zeroed, then filled by pb_frame_plan_of alone, and compared
 * whole (memcmp): a setting that reaches a resource reaches it through
 * here, and so is in the key. */
typedef struct pb_frame_shape {
  const struct pb_gpu_scene *gs;          /* the buffers the passes bind */
  const struct pb_photon_map *photon_map; /* a map made by the host (tests):
                                             no tracer */
  uint32_t width, height, band_pixels;    /* band_pixels: the targets' size */
  int photons;                            /* the photon stages run */
  pb_render_plan scene;                   /* the passes' specialization
                                             constants, normal maps */
  pb_tracer_desc tracer;                  /* pb_tracer_create's (photons
                                             without a host map) */
  pb_estimator_desc estimator;            /* pb_estimator_create's */
  uint32_t upsample_levels;               /* pb_upsample_create's (none with
                                             normal maps) */
} pb_frame_shape;

typedef struct pb_frame_plan {
  pb_frame_shape shape;     /* the context key */
  uint32_t spp;             /* samples per pixel (at least `iters`) */
  uint32_t iters;           /* photon maps (iterations); 1 without photons */
  int photons;              /* shape.photons */
  uint32_t band_rows, bands;/* rows per band (the last may have fewer) */
  size_t pixels;            /* width x height */
  int host_resolve;         /* PB_RESOLVE_ON_HOST=1: the host resolve of the
                               tests (readback.h), the reference */
  int readback;             /* PB_RENDER_READBACK_*: what the readback
                               brings (desc.readback where it may) */
  int nmap;                 /* normal-map targets (targets.h nmap) */
  int nmap_aovs;            /* eq. 20's AOVs leave the GPU */
  int own_chain;            /* an A-Trous filter chain made for the call
                               (atrous_iterations without io.filters) */
  int post_gpu;             /* filters and eq. 20 after the resolve, on the
                               GPU (one band, not the host resolve) */
  int chain_gpu;            /* ... with a filter chain */
  int sc_on;                /* eq. 20 (shading_correction.h) */
  int still_gpu;            /* io.still_sum's means on the GPU */
  int defer;                /* frames in flight: the last submission is
                               not waited for (render.h in_flight) */
  pb_gpu_frame frame;       /* the frame's constants (per band: pixel_base,
                               pixel_count) */
} pb_frame_plan;

/* PB_ERR_USAGE for settings out of range, PB_ERR_LIMIT for a row that does
 * not fit a storage buffer; creates nothing. */
pb_result pb_frame_plan_of(pb_gpu *g, const pb_scene *s, const struct pb_gpu_scene *gs, int camera, uint32_t width,
                           uint32_t height, const pb_render_desc *d, const pb_render_io *io, pb_frame_plan *out);

#endif
