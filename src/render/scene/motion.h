/* Motion vectors (the temporal filter's reprojection, seed 001
 * 24.4.1 "using velocity vectors"): for each pixel, where the surface point
 * its centre sees was in the previous frame, on the previous frame's
 * screen, and at which camera depth.
 *
 * The point is the first hit of the pixel-centre ray (the G-buffer's camera
 * ray, gbuffer.comp, at the pixel centre), traced on the GPU against the
 * current scene; its triangle and barycentrics give the same point on the
 * triangle's previous vertex positions (triangle i is the same triangle at
 * every time: pb_scene_set_time), projected by the previous camera. So
 * camera motion, moving objects and moving cameras are all covered; what
 * a mirror or glass shows (specular eye chains) moves with the surface it
 * is seen in, not with the object reflected (the first hit is the mirror). */
#ifndef PB_RENDER_MOTION_H
#define PB_RENDER_MOTION_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/render.h"
#include "scene/scene.h"

/* Per pixel, 4 floats (top row first):
 *   dx, dy  previous-frame screen position minus this pixel's centre, in
 *           pixels (x right, y down);
 *   z       the point's camera depth in the previous frame (along the
 *           previous camera's forward axis);
 *   valid   1 when the ray hit a surface that was in front of the previous
 *           camera, else 0 (the other three are then 0). */
enum { PB_MOTION_CHANNELS = 4 };

/* The pass (shaders/scene/motion.comp), kept between the frames of a sequence:
 * its pipeline, the parameters, the previous positions and the output. */
typedef struct pb_motion_pass pb_motion_pass;
pb_result pb_motion_pass_create(pb_gpu *g, uint32_t width, uint32_t height, uint32_t vertex_count,
                                pb_motion_pass **out);
void pb_motion_pass_destroy(pb_gpu *g, pb_motion_pass *m);
/* s: the scene as posed for this frame, gs its GPU copy (updated to the
 * same pose). prev_positions: s's vertex positions in the previous frame
 * (vertex_count entries), or NULL when no geometry moved. cam/prev_cam:
 * this and the previous frame's camera. motion: width x height x 4 floats
 * out. gpu_ms (may be NULL): the pass's time. */
pb_result pb_motion_pass_run(pb_gpu *g, pb_motion_pass *m, const pb_scene *s, const pb_gpu_scene *gs,
                             const float (*prev_positions)[3], const pb_camera *cam, const pb_camera *prev_cam,
                             float *motion, double *gpu_ms);

/* The device-side pass of a frame (the filter chain, filters.h): prepare
 * (the parameters and previous positions to the GPU: scene data, not
 * pixels; and the bindings) before pb_gpu_begin, record inside; the
 * vectors then lie in pb_motion_pass_output, never on the host. */
pb_result pb_motion_pass_prepare(pb_gpu *g, pb_motion_pass *m, const pb_scene *s, const pb_gpu_scene *gs,
                                 const float (*prev_positions)[3], const pb_camera *cam, const pb_camera *prev_cam);
pb_result pb_motion_pass_record(pb_gpu *g, pb_motion_pass *m);
const pb_gpu_buffer *pb_motion_pass_output(const pb_motion_pass *m);

/* One-shot: create, run, destroy (tests). */
pb_result pb_motion_vectors(pb_gpu *g, const pb_scene *s, const pb_gpu_scene *gs, const float (*prev_positions)[3],
                            const pb_camera *cam, const pb_camera *prev_cam, uint32_t width, uint32_t height,
                            float *motion, double *gpu_ms);

/* The camera rays through the centres of pixels first .. first + count - 1
 * of a width x height image (row-major, top row first): gbuffer.comp's
 * camera ray at one sample per pixel (pb_camera_ray: from the near clip
 * plane, tmin 0, tmax to the far plane). Shared with the ray benchmarks
 * (bench/). */
void pb_camera_primary_rays(const pb_camera *c, uint32_t width, uint32_t height, size_t first, uint32_t count,
                            pb_gpu_ray *rays);

/* Projects world point p by camera c onto a width x height image: pixel
 * coordinates (x right, y down, pixel centres at +0.5) and camera depth, as
 * motion.comp does on the GPU. Returns 0 when p is not in front of the
 * camera. */
int pb_camera_project(const pb_camera *c, uint32_t width, uint32_t height, const float p[3], float *x, float *y,
                      float *depth);

#endif
