/* Reflective shadow maps for the photon tracer's first bounce (seed 001
 * 24.2.1): src/render/photon/photon_rsm.c, shaders/photon_rsm.comp. Internal to the
 * tracer (photon_trace.c), selected by pb_photon_trace_desc.first_bounce. */
#ifndef PB_RENDER_PHOTON_RSM_H
#define PB_RENDER_PHOTON_RSM_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/render.h"
#include "scene/scene.h"

typedef struct pb_photon_rsm pb_photon_rsm;

/* One map per entry of the tracer's light table (`light[i]` the scene light
 * of entry i), res x res texels per face (6 faces for point lights).
 * caustic_share in [0, 1): the share of each map's photons its specular
 * texels get at least (PB_RSM_MODE_BOOST in photon_rsm.comp); 0: by
 * reflected power alone. */
pb_result pb_photon_rsm_create(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const uint32_t *light,
                               uint32_t entries, uint32_t res, const float center[3], float radius,
                               float caustic_share, pb_photon_rsm **out);
/* Binds the maps' buffers and the scene (before pb_gpu_begin); `frame` is the
 * tracer's pb_gpu_frame buffer. */
pb_result pb_photon_rsm_bind(pb_gpu *g, pb_photon_rsm *r, const pb_gpu_buffer *frame);
/* Records render + barrier + scan + barrier into the open command buffer. */
pb_result pb_photon_rsm_record(pb_gpu *g, pb_photon_rsm *r);
/* The pb_gpu_rsm_light table and the pb_gpu_rsm_texel array. */
const pb_gpu_buffer *pb_photon_rsm_lights(const pb_photon_rsm *r);
const pb_gpu_buffer *pb_photon_rsm_texels(const pb_photon_rsm *r);
uint32_t pb_photon_rsm_texel_count(const pb_photon_rsm *r);
/* After the maps ran: the lights whose photons start from their map (all
 * lights with a map, or with `auto_mode` those whose coverage is below
 * PB_RSM_AUTO_COVERAGE) and the smallest coverage of a light with a map
 * (1 when none has one). */
pb_result pb_photon_rsm_coverage(pb_gpu *g, const pb_photon_rsm *r, int auto_mode, uint32_t *mapped,
                                 float *min_coverage);
/* After the maps ran: the largest boost of a light's specular texels (1:
 * none; pb_gpu_rsm_light.boost). */
pb_result pb_photon_rsm_boost(pb_gpu *g, const pb_photon_rsm *r, float *max_boost);
void pb_photon_rsm_destroy(pb_gpu *g, pb_photon_rsm *r);

#endif
