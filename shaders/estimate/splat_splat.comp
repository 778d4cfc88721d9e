#version 450
// Screen-space splatting, pass 2 of 3 (seed 001 24.3.1-24.3.2, eq. 2-9):
// one thread per stored photon, scattering its kernel into the pixels it
// covers (the chapter rasterises an icosahedron per photon; here a compute
// thread walks the kernel's screen rectangle: Vulkan compute only, like the
// rest of the renderer).
//
// Uniform scaling (24.3.1.1), the product s_l s_d:
//   eq. 2  s_l = min(l / l_max, 1), l the photon's ray length (stored by
//          the tracer, pb_gpu_photon.ray_length), floored at 0.1 as the
//          chapter's listing does (clamp(ray_length / MAX_RAY_LENGTH, .1f,
//          1.0f)); a map without ray lengths (0) takes s_l = 1.
//   eq. 3  a_view = z_view^2 (2 tan(alpha_x / 2) t_x / r_x)
//                            (2 tan(alpha_y / 2) t_y / r_y),
//          the view-space area of a tile at the photon's depth (the printed
//          equation is garbled; this is what its text and eq. 4 say). Our
//          camera's pixel pitch at unit distance is |dx|, |dy|
//          (pb_gpu_camera), so eq. 4's c_tile = t^2 |dx dy| for square
//          tiles of t pixels (orthographic: a_view = c_tile, no z^2).
//   eq. 5  r = sqrt(a_view / (pi n_p)), as the listing computes it (the
//          printed equation is garbled): the radius of a disc holding one
//          of the tile's n_p photons.
//   eq. 6  s_d = clamp(r, r_min, r_max) n_tile as printed, "n_tile equal to
//          the number of photons that we expect to contribute to each
//          pixel". A disc of radius k r holds k^2 photons, so for n_tile
//          photons per point the factor is sqrt(n_tile) (derived: the
//          printed product, taken literally, overlaps n_tile^2); and the
//          clamp is applied to the product so that r_max bounds the kernel
//          (and the work per photon) whatever n_tile is:
//          s_d = clamp(sqrt(n_tile) r, r_min, r_max).
// Shape (24.3.1.2): a tri-axial ellipsoid on the photon's surface, axes
//   n = omega_g (the stored normal), magnitude s_n s_l s_d;
//   u = omega_i projected onto the kernel plane, magnitude s_u s_l s_d with
//   eq. 7  s_u = min(1 / (omega_g . omega_i), s_max);
//   t = n x u, magnitude s_l s_d;
//   eq. 8  (the kernel's vertices in that basis) is what the rectangle
//          walk below inverts: a G-buffer point x is inside when its
//          coordinates along u and t fall in the unit disc.
// Depth test (24.3.2): "a clipping operation for the world-space distance
//   between the surface and the kernel plane against a constant value
//   scaled by the kernel compression constant": |(x - x_p) . n| <= s_n s_l
//   s_d, the kernel's half-thickness (its scale s_l s_d as the constant,
//   derived: the chapter's MAX_DEPTH is not given).
// eq. 9  E_i = Phi / a, a = pi |u| |t| = pi (s_l s_d)^2 s_u, the constant
//   kernel of the chapter, added into the pixel's irradiance, with the
//   power-weighted direction (24.3.2: "we accumulate the average light
//   direction as a weighted sum"). Caustic photons go into their own sum.
// The frustum culling of 24.2.1 is done on points, as the chapter's, but
// only for the tile count: a photon in front of the camera whose centre is
// off screen still splats into the pixels its kernel reaches (the
// chapter's suggested fix, "expanding the camera frustum used for the
// culling", which removes the darkening at the image's border).
// Float adds are compare-and-swap loops on the uint target (no
// shaderBufferFloat32AtomicAdd needed); the order of the adds varies
// between runs, so results agree to rounding, not bit for bit.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_splat.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

layout(std430, set = 0, binding = PB_BIND_FRAME) readonly buffer FrameBuf { pb_gpu_frame frame; };
layout(std430, set = 0, binding = PB_BIND_GBUFFER) readonly buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_SPLAT_BIND_TARGET) buffer Target { uint target[]; };
#include "common/camera.glsl"
#include "common/splat.glsl"

void pb_splat_add(uint word, float v) {
  if (v == 0.0) return;
  uint old = target[word];
  for (;;) {
    uint want = floatBitsToUint(uintBitsToFloat(old) + v);
    uint prev = atomicCompSwap(target[word], old, want);
    if (prev == old) break;
    old = prev;
  }
}

bool pb_splat_finite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

void main() {
  uint i = pb_splat_gid();
  if (i >= pb_splat_stored()) return;
  pb_gpu_photon p = photons[i];
  vec2 px;
  float z;
  if (pb_splat_cull(p, px, z) >= 2u) return;
  pb_gpu_camera c = frame.cam;
  bool ortho = c.orthographic != 0u;

  // Uniform scaling, eq. 2-6.
  float n_p = float(max(tiles[pb_splat_tile(px)], 1u));
  float c_tile = float(sp.tile * sp.tile) * abs(c.dx * c.dy);   // eq. 4
  float a_view = ortho ? c_tile : z * z * c_tile;               // eq. 3-4
  float r = sqrt(a_view / (PB_SPLAT_PI * n_p));                 // eq. 5
  float s_d = clamp(sqrt(sp.n_tile) * r, sp.r_min, sp.r_max);   // eq. 6 (derived, above)
  float s_l = p.ray_length > 0.0 ? clamp(p.ray_length / sp.l_max, 0.1, 1.0) : 1.0; // eq. 2
  float R = s_l * s_d * sp.footprint_scale;

  // Shape, eq. 7-8.
  vec3 n = p.normal;
  float cos_t = clamp(dot(n, p.wi), 0.0, 1.0);
  float s_u = min(1.0 / max(cos_t, 1e-6), sp.s_max);           // eq. 7
  vec3 u = p.wi - cos_t * n;
  float lu = length(u);
  if (lu > 1e-6) {
    u /= lu;
  } else { // normal incidence: any tangent (s_u = 1, the kernel is a disc)
    vec3 a = abs(n.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0);
    u = normalize(cross(n, a));
  }
  vec3 t = cross(n, u);
  float U = s_u * R, T = R, N = sp.s_n * R;
  float area = PB_SPLAT_PI * U * T;                             // eq. 9's a
  vec3 E = p.power / area;                                      // eq. 9
  if (!(area > 0.0) || !pb_splat_finite(E) || !pb_splat_finite(p.position)) return;
  bool caustic = (p.flags & PB_PHOTON_CAUSTIC) != 0u;
  float w = dot(E, vec3(0.2126, 0.7152, 0.0722));

  // The kernel's screen rectangle: the projection of its oriented bounding
  // box (centre +- U u +- T t +- N n: the 8 corners); the whole image when
  // the box reaches the near plane.
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  bool whole = false;
  for (int k = 0; k < 8; ++k) {
    vec3 q = p.position + (((k & 1) != 0) ? U : -U) * u + (((k & 2) != 0) ? T : -T) * t +
             (((k & 4) != 0) ? N : -N) * n;
    vec2 qp;
    float qz;
    if (!pb_camera_project(c, q, qp, qz) || qz < c.clip_near) {
      whole = true;
      break;
    }
    lo = min(lo, qp);
    hi = max(hi, qp);
  }
  vec2 key = vec2(float(frame.key_x0), float(frame.key_y0));
  lo -= key;
  hi -= key;
  if (whole) {
    lo = vec2(0.0);
    hi = vec2(float(frame.width), float(frame.height));
  }
  float ext = float(sp.max_extent);
  bool clipped = any(lessThan(lo, px - ext)) || any(greaterThan(hi, px + ext));
  lo = max(lo, px - ext);
  hi = min(hi, px + ext);
  // This band's rows.
  uint row0 = frame.pixel_base / frame.width;
  uint row1 = (frame.pixel_base + frame.pixel_count + frame.width - 1u) / frame.width; // exclusive
  int x0 = int(max(floor(lo.x), 0.0)), x1 = int(min(floor(hi.x), float(frame.width) - 1.0));
  int y0 = int(max(floor(lo.y), float(row0))), y1 = int(min(floor(hi.y), float(row1) - 1.0));
  uint tested = 0u, splatted = 0u;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      uint pix = uint(y) * frame.width + uint(x);
      if (pix < frame.pixel_base || pix >= frame.pixel_base + frame.pixel_count) continue;
      uint gi = pix - frame.pixel_base;
      pb_gpu_gbuffer g = gbuffer[gi];
      if (g.prim == PB_GPU_MISS) continue;
      tested++;
      vec3 d = g.position - p.position;
      if (abs(dot(d, n)) > N) continue; // the depth test (24.3.2)
      float a = dot(d, u) / U, b = dot(d, t) / T;
      if (a * a + b * b > 1.0) continue;
      uint base = gi * PB_SPLAT_PIXEL_WORDS;
      uint o = base + (caustic ? PB_SPLAT_W_CAU : PB_SPLAT_W_IND);
      pb_splat_add(o, E.x);
      pb_splat_add(o + 1u, E.y);
      pb_splat_add(o + 2u, E.z);
      if (w > 0.0) {
        pb_splat_add(base + PB_SPLAT_W_DIR, w * p.wi.x);
        pb_splat_add(base + PB_SPLAT_W_DIR + 1u, w * p.wi.y);
        pb_splat_add(base + PB_SPLAT_W_DIR + 2u, w * p.wi.z);
        pb_splat_add(base + PB_SPLAT_W_WSUM, w);
      }
      atomicAdd(target[base + PB_SPLAT_W_HITS], 1u);
      splatted++;
    }
  }
  if ((sp.flags & PB_SPLAT_STATS) != 0u) {
    atomicAdd(stats.tested, tested);
    atomicAdd(stats.splatted, splatted);
    if (clipped) atomicAdd(stats.clipped, 1u);
  }
}
