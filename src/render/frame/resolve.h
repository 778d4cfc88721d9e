/* The resolve pass (resolve.c, shaders/frame/resolve.comp): records, into the
 * frame's command buffer after a band's last sample, the means of the
 * band's accumulators as the AOV planes of shared/pb_resolve.h, with
 * non-finite values replaced by 0 and counted in targets.guard, and (photon
 * stages on) k_PD's sums added into targets.kpd. */
#ifndef PB_RENDER_RESOLVE_H
#define PB_RENDER_RESOLVE_H

#include "gpu/gpu.h"
#include "render/frame/targets.h"

/* A pipeline bound to t's buffers (valid while t lives). */
pb_result pb_resolve_create(pb_gpu *g, const pb_frame_targets *t, pb_gpu_pipeline *out);
/* inv_spp: 1 / samples accumulated; opaque: beauty alpha 1. */
pb_result pb_resolve_record(pb_gpu *g, const pb_gpu_pipeline *p, const pb_frame_targets *t, uint32_t pixels,
                            float inv_spp, int opaque);

#endif
