/* The photon map's records, shared by the photon tracer (emit/trace passes)
 * and the density estimators (LBVH + gather now; kNN, screen-space splatting
 * and the view-sample hierarchy later). Included after pb_gpu.h, which
 * defines PB_STRUCT / PB_VEC3 / PB_CONST for C and GLSL.
 *
 * Seed 000 (Fabianowski & Dingliana), section 3-4: every stored hit carries a
 * footprint, a skewed ellipsoid whose two in-surface semi-axes come from the
 * photon's positional differentials times the global spacing Delta
 * (eq. 8-9), rescaled after tracing by |dP|^(-3/4) and the smoothing factor s
 * (caustic photons: uncompressed, times s_caustic), clamped to r_max; its third axis is the
 * surface normal, of half-length `normal_extent`. */
#ifndef PB_PHOTON_SHARED_H
#define PB_PHOTON_SHARED_H

/* flags: bit 0 caustic (only specular interactions between the light and
 * this diffuse hit); bits 8..15 the number of diffuse bounces before this hit
 * (1 = first stored bounce, since the first hit is direct light and is never
 * stored, seed 001 24.2.1). */
PB_CONST(PB_PHOTON_CAUSTIC, 1u)
PB_CONST(PB_PHOTON_BOUNCE_SHIFT, 8u)

/* A stored photon hit, 96 bytes.
 *  position  world-space hit point (metres)
 *  power     flux carried, W per linear Rec.709 channel
 *  radius    bounding radius of the footprint ellipse after rescaling and the
 *            r_max clamp (max of |axis_u|, |axis_v| is a lower bound; for a
 *            skewed ellipse the tracer stores the true semi-major length)
 *  wi        unit direction the photon came from (points away from the
 *            surface, into the hemisphere of `normal`)
 *  normal    unit geometric normal of the hit surface, on the side of wi
 *  axis_u, axis_v  the footprint's semi-axes in world space (in the tangent
 *            plane; skewed, not necessarily orthogonal)
 *  normal_extent   half-thickness of the ellipsoid along `normal`
 *  ray_length      length of the segment that ended at this hit, m (seed 001
 *            24.2.3 stores t with each photon; its eq. 2 scales the splat
 *            kernel by it); 0: unknown (maps made by the host) */
PB_STRUCT(pb_gpu_photon) {
  PB_VEC3(position);
  uint flags;
  PB_VEC3(power);
  float radius;
  PB_VEC3(wi);
  float normal_extent;
  PB_VEC3(normal);
  uint path;            /* index of the emitted photon path (debugging, tests) */
  PB_VEC3(axis_u);
  float ray_length;
  PB_VEC3(axis_v);
  float pad1;
} PB_END(pb_gpu_photon)

/* A photon of the sorted map, 48 bytes (the LBVH's copy in Morton
 * order, written by lbvh_climb.comp and read by the gather and kNN through
 * common/photon_pack.glsl; the tracer's map keeps pb_gpu_photon). Three uvec4:
 *  w0  position (f32 x3), normal_extent (f32)
 *  w1  power (f32 x3), scale s = max(radius, |axis_u|, |axis_v|) (f32)
 *  w2  x: normal, octahedral (Cigolle et al. 2014), 2 x snorm16
 *      y: wi, octahedral, 2 x 12-bit snorm (bits 0-23); bits 24-31 the
 *         flags: bit 24 caustic, bits 25-31 the diffuse bounces (at most 127)
 *      z, w: axis_u and axis_v / s in the tangent frame of the decoded
 *         normal (pb_basis, common/basis.glsl), 2 x snorm16 each
 * Position, power and normal extent are exact; the normal within 1e-4 rad,
 * wi within 1e-3 rad, the axes within 3e-5 s (the footprint lies in the
 * tangent plane: photon_trace.comp projects the differentials onto it).
 * Not kept: path and ray_length (no estimator of the sorted map reads
 * them). */
PB_STRUCT(pb_gpu_photon_packed) {
  PB_VEC3(position);
  float normal_extent;
  PB_VEC3(power);
  float scale;
  uint normal_oct;
  uint wi_flags;
  uint axis_u2;
  uint axis_v2;
} PB_END(pb_gpu_photon_packed)
PB_CONST(PB_PHOTON_PACKED_WORDS4, 3u) /* uvec4 per packed photon */

/* Counters written by the tracer (atomics), 32 bytes. */
PB_STRUCT(pb_gpu_photon_counts) {
  uint stored;          /* photons written (<= capacity) */
  uint caustic;         /* of which caustic */
  uint emitted;         /* photon paths started */
  uint overflow;        /* hits dropped because the buffer was full */
  uint clamped;         /* of the stored, footprints shrunk to r_max */
  uint pad0, pad1, pad2;
} PB_END(pb_gpu_photon_counts)

#ifndef PB_GLSL
#include <stddef.h>
_Static_assert(sizeof(pb_gpu_photon) == 96, "pb_gpu_photon size");
_Static_assert(offsetof(pb_gpu_photon, flags) == 12, "pb_gpu_photon.flags");
_Static_assert(offsetof(pb_gpu_photon, power) == 16, "pb_gpu_photon.power");
_Static_assert(offsetof(pb_gpu_photon, radius) == 28, "pb_gpu_photon.radius");
_Static_assert(offsetof(pb_gpu_photon, wi) == 32, "pb_gpu_photon.wi");
_Static_assert(offsetof(pb_gpu_photon, normal_extent) == 44, "pb_gpu_photon.normal_extent");
_Static_assert(offsetof(pb_gpu_photon, normal) == 48, "pb_gpu_photon.normal");
_Static_assert(offsetof(pb_gpu_photon, path) == 60, "pb_gpu_photon.path");
_Static_assert(offsetof(pb_gpu_photon, axis_u) == 64, "pb_gpu_photon.axis_u");
_Static_assert(offsetof(pb_gpu_photon, ray_length) == 76, "pb_gpu_photon.ray_length");
_Static_assert(offsetof(pb_gpu_photon, axis_v) == 80, "pb_gpu_photon.axis_v");
_Static_assert(sizeof(pb_gpu_photon_counts) == 32, "pb_gpu_photon_counts size");
_Static_assert(sizeof(pb_gpu_photon_packed) == 48, "pb_gpu_photon_packed size");
_Static_assert(offsetof(pb_gpu_photon_packed, normal_extent) == 12, "pb_gpu_photon_packed.normal_extent");
_Static_assert(offsetof(pb_gpu_photon_packed, scale) == 28, "pb_gpu_photon_packed.scale");
_Static_assert(offsetof(pb_gpu_photon_packed, normal_oct) == 32, "pb_gpu_photon_packed.normal_oct");
_Static_assert(offsetof(pb_gpu_photon_packed, axis_v2) == 44, "pb_gpu_photon_packed.axis_v2");
#endif

#endif
