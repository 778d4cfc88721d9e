/* The implementations' side of tracer.h. */
#ifndef PB_RENDER_TRACER_INTERNAL_H
#define PB_RENDER_TRACER_INTERNAL_H

#include "render/photon/tracer.h"
#include "shared/pb_photon.h"

typedef struct pb_tracer_ops {
  const char *name;
  pb_result (*update)(pb_gpu *g, pb_tracer *t, const pb_scene *s);
  uint32_t (*stats)(const pb_tracer *t, pb_tracer_stat *out, uint32_t max);
  void (*destroy)(pb_gpu *g, pb_tracer *t); /* the implementation's own parts */
} pb_tracer_ops;

struct pb_tracer {
  const pb_tracer_ops *ops;
  pb_photon_tracer *photon;   /* every implementation traces with it */
  pb_image_maps *maps;        /* images */
  pb_gpu_photon *hist;        /* pb_tracer_radius_histogram's host copy */
  size_t hist_cap;            /* ... its room, in photons */
};

/* tracer_images.c: turns t (a BVH tracer just made) into an images tracer. */
pb_result pb_tracer_images_init(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const pb_image_maps_desc *d,
                                pb_tracer *t);

#endif
