/* The reference renderer's Embree scene: closest hit, occlusion, and the
 * self-intersection offset (accel.c). */
#ifndef PB_REF_ACCEL_H
#define PB_REF_ACCEL_H

#include <embree3/rtcore.h>

#include "ref/vec.h"
#include "scene/scene.h"

typedef struct pb_ref_accel {
  RTCDevice device;
  RTCScene scene;
} pb_ref_accel;

typedef struct pb_ref_hit {
  float t;
  uint32_t prim;
  float u, v; /* Embree barycentrics: p = (1-u-v) p0 + u p1 + v p2 */
} pb_ref_hit;

/* The scene's indices must be in range (ref.c checks them first). */
pb_result pb_ref_accel_create(const pb_scene *s, pb_ref_accel *a);
void pb_ref_accel_destroy(pb_ref_accel *a);
/* Closest hit in (0, tmax]; returns 0 on a miss. */
int pb_ref_intersect(const pb_ref_accel *a, v3 o, v3 d, float tmax, pb_ref_hit *hit);
/* 1 when anything lies in (0, tmax). */
int pb_ref_occluded(const pb_ref_accel *a, v3 o, v3 d, float tmax);

/* Waechter & Binder, "A Fast and Robust Method for Avoiding
 * Self-Intersection", Ray Tracing Gems ch. 6: moves p off the surface along
 * the geometric normal n (pointing to the side the new ray leaves) by a fixed
 * number of float ULPs, so the offset scales with |p| and works at any
 * distance from the origin; near the origin (|p| < 1/32) a small absolute
 * offset takes over where ULPs are too fine. */
v3 pb_offset_ray(v3 p, v3 n);

#endif
