/* The rays of a camera for one image: the one definition every renderer
 * uses (the GPU's G-buffer and motion passes through pb_gpu_camera and
 * shaders/common/camera.glsl, the reference, the POV-Ray export, the ray
 * benchmarks).
 *
 * Blender's conventions (BKE_camera_params_compute_viewplane, 3.4): the
 * field of view (or orthographic size) spans the fitted side; AUTO fits the
 * larger side; lens shift moves the window by shift x the fitted side's
 * extent, so shift 0.5 moves it by half the picture's larger side. A crop
 * (Blender's border, `render --crop`) is the same window with its corner
 * moved, so every pixel of a crop sees exactly what the full frame's pixel
 * sees there (the same floats: the crop's pixels are traced at the full
 * image's positions). */
#ifndef PB_SCENE_CAMERA_H
#define PB_SCENE_CAMERA_H

#include <stdint.h>

#include "scene/gltf_doc.h"
#include "scene/scene.h"
#include "shared/pb_gpu.h"

/* The window of camera c for a full_w x full_h image, in double: width and
 * height (at distance 1 for perspective, metres for orthographic) and the
 * centre's offset right and up from the axis (the lens shift). */
void pb_camera_window(const pb_camera *c, uint32_t full_w, uint32_t full_h, double *width, double *height,
                      double *cx, double *cy);

/* The same window as a pb_gpu_camera for a full_w x full_h image. A crop
 * of that image uses the same view at the full image's pixel positions
 * (the GPU's frame adds key_x0, key_y0). */
void pb_camera_view(const pb_camera *c, uint32_t full_w, uint32_t full_h, pb_gpu_camera *out);

/* The camera ray through image position (px, py) (pixels, top row first;
 * pixel centres at +0.5): origin on the near clip plane, unit direction,
 * t0 the distance from the camera (its position, or its plane when
 * orthographic) to that origin along the ray, tmax the ray's length to the
 * far plane (INFINITY without one). The camera depth of a hit at distance t
 * from the origin is (t0 + t) * dot(dir, forward). */
void pb_camera_ray(const pb_gpu_camera *v, float px, float py, float org[3], float dir[3], float *t0,
                   float *tmax);

/* The same through a point of the aperture: lens a sample in [0, 1)^2
 * (NULL, or a view without aperture: the pinhole ray above, the centre's;
 * motion vectors and reprojection use it). Cycles 3.4's thin lens
 * (kernel/camera/camera.h): perspective rays leave the lens point toward
 * the pinhole ray's point at depth `focus`; orthographic ones leave the
 * window point plus the lens offset on the near plane toward forward x
 * focus from the lens centre; panoramic ones use the plane normal to the
 * pinhole ray. A panoramic ray starts clip_near along itself (t0 =
 * clip_near; its camera depth is the hit's distance from `position`, as
 * Cycles' camera_z_depth). Returns 0, with tmax 0, where the image
 * position has no ray (outside a fisheye's circle or the mirror ball):
 * the pixel stays black and uncovered, as in Cycles. */
int pb_camera_ray_lens(const pb_gpu_camera *v, float px, float py, const float lens[2], float org[3], float dir[3],
                       float *t0, float *tmax);

/* Projects world point p: image position (pixels, as pb_camera_ray takes
 * them) and camera depth along forward (panoramas: the distance, and the
 * inverse of their mapping). Returns 0 when p is not in front of the
 * camera plane (depth <= 0), outside a panorama's field, or the position
 * is not finite. The pinhole's projection: depth of field is not undone. */
int pb_camera_view_project(const pb_gpu_camera *v, const float p[3], float *x, float *y, float *depth);

/* The size of one pixel on a surface at camera depth z, metres (reference
 * and photon radii): |dy| z for perspective, |dy| for orthographic. */
float pb_camera_pixel_size(const pb_gpu_camera *v, float z);

/* A glTF camera's projection (position and frame left 0): the plain
 * perspective or orthographic camera, replaced by its
 * PHOTONBRIDGE_blender extension where it has one (sensor fit, lens
 * shift, clip range, orthographic scale, depth of field, panoramas;
 * exporters/blender/
 * PHOTONBRIDGE_blender.md). Errors name the JSON path: PB_ERR_SCENE_INVALID
 * for a value of the wrong type or out of range, PB_ERR_SCENE_UNSUPPORTED
 * for a camera type other than PERSP/ORTHO/PANO or a panorama type other
 * than EQUIRECTANGULAR, FISHEYE_EQUIDISTANT, FISHEYE_EQUISOLID, MIRRORBALL. */
pb_result pb_camera_projection_from_gltf(const char *path, int index, const pb_gltf_camera *c, pb_camera *out);

#endif
