/* The readback: the one place a frame's pixels come to the host.
 * Everything else stays in the targets (targets.h) on the GPU; what the
 * host needs (the AOVs of pb_render_result, for EXR and PNG output and the
 * tests; the progress preview; the guard count) is copied here, from
 * host-visible targets (a memcpy where the memory is cached, as on a CPU
 * device; otherwise one staged copy of the whole range), all of it counted
 * as read back (pb_gpu_transfers.readback_bytes), apart from the transfers
 * a frame should not make. */
#ifndef PB_RENDER_READBACK_H
#define PB_RENDER_READBACK_H

#include <stddef.h>

#include "gpu/gpu.h"
#include "render/render.h"
#include "render/frame/targets.h"
#include "render/filter/temporal.h"

/* mode (PB_RENDER_READBACK_*, render.h): ALL reads what follows; BEAUTY
 * the beauty plane alone into out->beauty, STATS no plane; neither reads
 * the k_PD plane nor adds to k_sum and hit_sum (the resolve's reduction
 * has them: pb_readback_kpd), the other arrays left alone (the host
 * resolve of the tests always reads all).
 * The resolved band (pixels at pixel_base of an image of n pixels) into
 * out's arrays (allocated by the caller: beauty .. emission, and indirect,
 * caustic with photons); with nmap_aovs also geo_normal, photon_dir and
 * shading_normal (allocated here on first use). k_sum, hit_sum (photons):
 * the band's raw sums for k_PD, added. inv_spp and opaque: the resolve's
 * (pb_resolve_record), for the host reference: with PB_RESOLVE_ON_HOST=1 in
 * the environment (a test hook) the planes are computed here, from the
 * accumulators, by the host resolve the pass replaced. */
pb_result pb_readback_band(pb_gpu *g, const pb_frame_targets *t, int mode, uint32_t pixels, size_t pixel_base,
                           size_t n, float inv_spp, int opaque, int nmap_aovs, pb_render_result *out, double *k_sum,
                           double *hit_sum);
/* Frames in flight: records, into the recording command buffer after the
 * passes that write the planes (a barrier before), the copy of the band's
 * planes into ring slot `slot` (targets.h; pb_frame_targets_ring made it).
 * On a discrete GPU this copy is the download, made by the GPU while the
 * host works; on a CPU device it is a memcpy the driver's threads make. */
/* What is copied: with mode ALL every plane (as before the lean modes),
 * else only what the readback of `mode` reads (BEAUTY: the beauty plane,
 * STATS: none) and the planes in keep (pb_render_desc.keep_planes).
 * Returns the planes copied (PB_RENDER_KEEP bits, PB_RENDER_KEEP_ALL),
 * *bytes the bytes. */
uint64_t pb_readback_ring_record(pb_gpu *g, const pb_frame_targets *t, uint32_t slot, uint32_t pixels, int mode,
                                 uint64_t keep, uint64_t *bytes);
/* The planes pb_readback_ring_record copies for mode and keep. */
uint64_t pb_readback_ring_planes(int mode, uint64_t keep);
/* k_PD's sums over the frame, from the resolve's reduction (targets.kpd,
 * shared/pb_resolve.h pb_gpu_resolve_kpd; 16 bytes): photons gathered and
 * samples that hit, as the k_PD plane's sums (exact: they are counts).
 * Read once the frame's last submission finished, before the next frame
 * zeroes them. */
pb_result pb_readback_kpd(pb_gpu *g, const pb_frame_targets *t, double *k_sum, double *hit_sum);
/* pb_readback_band from ring slot `slot` (one band, the whole image)
 * instead of the planes, without waiting for a pending submission (which
 * writes the planes and the other slot, never this one). */
pb_result pb_readback_ring(pb_gpu *g, const pb_frame_targets *t, int mode, uint32_t slot, uint32_t pixels,
                           int nmap_aovs, pb_render_result *out, double *k_sum, double *hit_sum);
/* Every AOV of a frame's planes kept on the GPU (p: pb_render_result.gpu)
 * into out's non-NULL arrays (the caller allocates them; geo_normal ..
 * shading_normal allocated here as pb_readback_band does). */
pb_result pb_readback_planes(pb_gpu *g, const pb_render_gpu_planes *p, pb_render_result *out);
/* Non-finite values the resolve replaced since the guard was zeroed. */
pb_result pb_readback_guard(pb_gpu *g, const pb_frame_targets *t, uint64_t *count);
/* The temporal filter's counts of one frame (pb_gpu_temporal_stats in b,
 * 16 bytes), as stats (gpu_ms left alone). */
pb_result pb_readback_temporal_stats(pb_gpu *g, const pb_gpu_buffer *b, pb_temporal_stats *stats);
/* The mean beauty (RGBA) of the first n pixels' accumulators over `samples`
 * samples, non-finite values as 0 (render --preview). */
pb_result pb_readback_preview(pb_gpu *g, const pb_frame_targets *t, size_t n, uint32_t samples, float *beauty);

#endif
