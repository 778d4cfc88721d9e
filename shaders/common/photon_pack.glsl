// The sorted map's 48-byte photon record (shared/pb_photon.h,
// pb_gpu_photon_packed): packed by lbvh_climb.comp when it copies a photon
// into Morton order, unpacked by the gather and kNN. Half the 96 bytes of
// pb_gpu_photon: the climb writes, and every gather reads, 3 uvec4 instead
// of 6 per photon (on llvmpipe each is a loop over the 8 lanes; on a GPU
// the gather's memory traffic). src/render/photon/photon_pack.h is the host's
// decoder (tests), the same arithmetic in C.
#ifndef PB_PHOTON_PACK_GLSL
#define PB_PHOTON_PACK_GLSL
// The axes are stored in pb_basis's frame of the decoded normal; packer and
// unpacker both build it from that normal, so they agree exactly.
#include "common/basis.glsl"

vec2 pb_oct_sign(vec2 v) { return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }

// Octahedral map of a unit vector to [-1, 1]^2 (Cigolle et al. 2014,
// "A Survey of Efficient Representations for Independent Unit Vectors",
// sec. 3.1): project onto the octahedron |x| + |y| + |z| = 1, fold the
// lower half over the diagonals. A zero vector maps to (0, 0), i.e. +z.
vec2 pb_oct_encode(vec3 n) {
  float l1 = abs(n.x) + abs(n.y) + abs(n.z);
  vec2 p = l1 > 0.0 ? n.xy / l1 : vec2(0.0);
  return n.z >= 0.0 ? p : (1.0 - abs(p.yx)) * pb_oct_sign(p);
}
vec3 pb_oct_decode(vec2 e) {
  vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (v.z < 0.0) v.xy = (1.0 - abs(v.yx)) * pb_oct_sign(v.xy);
  return normalize(v);
}

// Two values in [-1, 1] as 12-bit signed-normalised integers in bits 0-23.
uint pb_pack_snorm12x2(vec2 v) {
  ivec2 q = ivec2(round(clamp(v, -1.0, 1.0) * 2047.0)) + 2048;
  return uint(q.x) | (uint(q.y) << 12);
}
vec2 pb_unpack_snorm12x2(uint w) {
  return vec2(float(int(w & 0xfffu) - 2048), float(int((w >> 12) & 0xfffu) - 2048)) * (1.0 / 2047.0);
}

void pb_photon_pack(pb_gpu_photon p, out uvec4 w0, out uvec4 w1, out uvec4 w2) {
  float s = max(p.radius, max(length(p.axis_u), length(p.axis_v)));
  float inv = s > 0.0 ? 1.0 / s : 0.0;
  uint no = packSnorm2x16(pb_oct_encode(p.normal));
  vec3 t, b;
  pb_basis(pb_oct_decode(unpackSnorm2x16(no)), t, b);
  uint bounces = min((p.flags >> PB_PHOTON_BOUNCE_SHIFT) & 0xffu, 127u);
  uint fl = (p.flags & PB_PHOTON_CAUSTIC) | (bounces << 1);
  w0 = uvec4(floatBitsToUint(p.position), floatBitsToUint(p.normal_extent));
  w1 = uvec4(floatBitsToUint(p.power), floatBitsToUint(s));
  w2 = uvec4(no, pb_pack_snorm12x2(pb_oct_encode(p.wi)) | (fl << 24),
             packSnorm2x16(vec2(dot(p.axis_u, t), dot(p.axis_u, b)) * inv),
             packSnorm2x16(vec2(dot(p.axis_v, t), dot(p.axis_v, b)) * inv));
}

vec3 pb_photon_unpack_normal(uvec4 w2) { return pb_oct_decode(unpackSnorm2x16(w2.x)); }
vec3 pb_photon_unpack_wi(uvec4 w2) { return pb_oct_decode(pb_unpack_snorm12x2(w2.y)); }

// The record as pb_gpu_photon: radius is the scale s (>= the semi-major
// axis), path and ray_length 0.
pb_gpu_photon pb_photon_unpack(uvec4 w0, uvec4 w1, uvec4 w2) {
  vec3 n = pb_photon_unpack_normal(w2), t, b;
  pb_basis(n, t, b);
  float s = uintBitsToFloat(w1.w);
  vec2 u = unpackSnorm2x16(w2.z) * s, v = unpackSnorm2x16(w2.w) * s;
  uint fl = w2.y >> 24;
  uint flags = (fl & PB_PHOTON_CAUSTIC) | ((fl >> 1) << PB_PHOTON_BOUNCE_SHIFT);
  return pb_gpu_photon(uintBitsToFloat(w0.xyz), flags, uintBitsToFloat(w1.xyz), s, pb_photon_unpack_wi(w2),
                       uintBitsToFloat(w0.w), n, 0u, u.x * t + u.y * b, 0.0, v.x * t + v.y * b, 0.0);
}

#endif
