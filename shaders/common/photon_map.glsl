// Photon map helpers shared by the LBVH passes and the gather: the exact
// AABB and the area of a footprint ellipsoid, Morton codes, order-preserving
// float <-> uint for atomic min/max. Include after pb_photon.h.
#ifndef PB_PHOTON_MAP_GLSL
#define PB_PHOTON_MAP_GLSL

// Half-extents of the AABB of the ellipsoid p + a u + b v + c (e n),
// a^2 + b^2 + c^2 <= 1: per axis k, sqrt(u_k^2 + v_k^2 + (e n_k)^2) (the
// support function of the ellipsoid along the axis; exact, also for skewed
// u, v).
vec3 pb_footprint_extent(vec3 u, vec3 v, vec3 n, float e) {
  vec3 w = n * e;
  return sqrt(u * u + v * v + w * w);
}

// Area of the footprint ellipse with conjugate semi-diameters u, v.
float pb_footprint_area(vec3 u, vec3 v) { return 3.14159265358979323846 * length(cross(u, v)); }

// 10 bits -> every third bit of 30 (Karras 2012).
uint pb_expand_bits(uint v) {
  v = (v * 0x00010001u) & 0xFF0000FFu;
  v = (v * 0x00000101u) & 0x0F00F00Fu;
  v = (v * 0x00000011u) & 0xC30C30C3u;
  v = (v * 0x00000005u) & 0x49249249u;
  return v;
}
// 30-bit Morton code of p inside [lo, hi] (x in the highest bit of each
// triple). A degenerate axis maps to 0.
uint pb_morton30(vec3 p, vec3 lo, vec3 hi) {
  vec3 ext = hi - lo;
  vec3 q = vec3(ext.x > 0.0 ? (p.x - lo.x) / ext.x : 0.0, ext.y > 0.0 ? (p.y - lo.y) / ext.y : 0.0,
                ext.z > 0.0 ? (p.z - lo.z) / ext.z : 0.0);
  q = clamp(q * 1024.0, vec3(0.0), vec3(1023.0));
  uvec3 c = uvec3(q);
  return (pb_expand_bits(c.x) << 2) | (pb_expand_bits(c.y) << 1) | pb_expand_bits(c.z);
}

uint pb_float_to_ordered(float f) {
  uint b = floatBitsToUint(f);
  return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}
float pb_ordered_to_float(uint o) {
  return uintBitsToFloat((o & 0x80000000u) != 0u ? (o & 0x7fffffffu) : ~o);
}

#endif
